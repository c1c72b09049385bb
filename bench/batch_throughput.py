#!/usr/bin/python3
"""Throughput of `skelseg batch` against a shell loop of `skelseg segment`.

Usage: bench/batch_throughput.py [--skelseg build/skelseg] [--resolution 192]
                                 [--small] [--out out/batch-throughput]

Full run: the 45 PSB models plus the shared shapes (../shared/data), every
mesh voxelised at --resolution. Both ways run over the same list in the same
run, on the same machine state: first a bash loop that calls
`skelseg segment INPUT -o OUT/loop/NAME` once per input, then
`skelseg batch LIST -o OUT/batch`. It prints shapes per minute for each and
their ratio (issue 10's target: batch >= 1.3x the loop on 2 cores) and
writes the figures to OUT/batch_throughput.json.

--small (CI, tools/run-benchmarks.sh): eight generated volumes at 40 voxels,
printed beside the committed baseline bench/batch_baseline.json. Timing on a
shared machine is noisy: the script reports, it never fails on speed (it
fails only when a run fails).
"""
import argparse, json, os, shutil, subprocess, sys, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SMALL_SHAPES = ["y-arms", "t-body", "box-tubes", "torus-limb", "figure", "capsule", "disc-limbs", "slab"]


def shared_inputs(data):
    psb = os.path.join(data, "psb", "off")
    shapes = os.path.join(data, "shapes")
    if not os.path.isdir(psb):
        sys.exit(f"batch_throughput: {psb} not found (the shared data); use --small")
    files = sorted((os.path.join(psb, f) for f in os.listdir(psb) if f.endswith(".off")),
                   key=lambda p: int(os.path.basename(p)[:-4]) if os.path.basename(p)[:-4].isdigit() else 0)
    if os.path.isdir(shapes):
        files += sorted(os.path.join(shapes, f) for f in os.listdir(shapes)
                        if f.endswith((".off", ".obj")))
    return files


def generated_inputs(skelseg, folder):
    os.makedirs(folder, exist_ok=True)
    files = []
    for i, shape in enumerate(SMALL_SHAPES):
        path = os.path.join(folder, f"{shape}.nrrd")
        subprocess.run([skelseg, "generate", shape, "-o", path, "--size", str(36 + 4 * (i % 3))],
                       check=True)
        files.append(path)
    return files


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skelseg", default=os.path.join(ROOT, "build", "skelseg"))
    ap.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    ap.add_argument("--resolution", type=int, default=192)
    ap.add_argument("--threads", type=int, default=0, help="0: all cores (both ways)")
    ap.add_argument("--small", action="store_true", help="a few generated shapes (CI)")
    ap.add_argument("--baseline", default=os.path.join(HERE, "batch_baseline.json"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "batch-throughput"))
    args = ap.parse_args()
    skelseg = os.path.abspath(args.skelseg)
    if not os.access(skelseg, os.X_OK):
        sys.exit(f"batch_throughput: {skelseg} not found (build the skelseg target)")

    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    inputs = (generated_inputs(skelseg, os.path.join(args.out, "in")) if args.small
              else shared_inputs(args.data))
    listing = os.path.join(args.out, "list.txt")
    with open(listing, "w") as f:
        f.write("".join(os.path.abspath(p) + "\n" for p in inputs))
    # Both ways read warm files.
    for p in inputs:
        with open(p, "rb") as f:
            f.read()
    common = ["--resolution", str(args.resolution), "--quiet"]
    if args.threads:
        common += ["--threads", str(args.threads)]

    loop_out = os.path.join(args.out, "loop")
    os.makedirs(loop_out)
    # The loop a user writes: one process per input, failures do not stop it.
    script = ('failed=0; while IFS= read -r f; do n=$(basename "$f"); n="${n%.*}"; '
              '"$0" segment "$f" -o "$1/$n" "${@:3}" || failed=$((failed+1)); '
              'done < "$2"; echo "$failed"')
    start = time.monotonic()
    loop = subprocess.run(["bash", "-c", script, skelseg, loop_out, listing] + common,
                          capture_output=True, text=True)
    loop_seconds = time.monotonic() - start
    loop_failed = int(loop.stdout.strip().splitlines()[-1]) if loop.stdout.strip() else -1

    batch_out = os.path.join(args.out, "batch")
    start = time.monotonic()
    batch = subprocess.run([skelseg, "batch", listing, "-o", batch_out] + common,
                           capture_output=True, text=True)
    batch_seconds = time.monotonic() - start
    summary = json.load(open(os.path.join(batch_out, "summary.json")))
    batch_failed = summary["counts"]["failed"]
    if batch.returncode not in (0, 5) or loop_failed != batch_failed:
        sys.stderr.write(batch.stderr[-2000:] + loop.stderr[-2000:])
        sys.exit(f"batch_throughput: runs failed (batch exit {batch.returncode}, "
                 f"{batch_failed} failed; loop {loop_failed} failed)")

    n = len(inputs)
    result = {
        "inputs": n,
        "failed": batch_failed,
        "resolution": args.resolution,
        "threads": args.threads or os.cpu_count(),
        "small": args.small,
        "loop_seconds": round(loop_seconds, 2),
        "batch_seconds": round(batch_seconds, 2),
        "loop_shapes_per_minute": round(n / loop_seconds * 60, 2),
        "batch_shapes_per_minute": round(n / batch_seconds * 60, 2),
        "ratio": round(loop_seconds / batch_seconds, 3),
        "load_average_1min": round(os.getloadavg()[0], 2),
    }
    with open(os.path.join(args.out, "batch_throughput.json"), "w") as f:
        json.dump(result, f, indent=2)
    print(f"{n} inputs ({batch_failed} failed both ways), resolution {args.resolution}, "
          f"{result['threads']} threads, load average {result['load_average_1min']}")
    print(f"  segment loop: {loop_seconds:8.1f} s  {result['loop_shapes_per_minute']:7.2f} shapes/min")
    print(f"  batch:        {batch_seconds:8.1f} s  {result['batch_shapes_per_minute']:7.2f} shapes/min")
    print(f"  batch / loop: {result['ratio']:.2f}x (target >= 1.3x on 2 cores)")
    if args.small and os.path.exists(args.baseline):
        base = json.load(open(args.baseline))
        print(f"  baseline ({os.path.relpath(args.baseline, ROOT)}): loop "
              f"{base['loop_shapes_per_minute']} shapes/min, batch {base['batch_shapes_per_minute']} "
              f"shapes/min, {base['ratio']}x (timing is not checked)")


if __name__ == "__main__":
    main()
