#!/usr/bin/python3
"""The reference runs of issue 4: end-to-end wall time, CPU time, peak memory
and serial share of `skelseg segment` on armadillo.obj and hand.off at
resolutions 256 and 400, repeated and summarised by the median.

Usage: bench/reference_runs.py [--skelseg build/skelseg] [--data ../shared/data]
                               [--resolutions 256,400] [--repeat 3] [--threads N]
                               [--out out/reference]
Prints a Markdown table (one row per model and resolution) and writes
OUT/reference.json with every run. Machines are shared and noisy: compare
medians, and read the load average printed with the table. With
--compare-exhaustive the table also says whether the band search's last run
wrote the same skeleton.ply, cuts.ply, segmentation.seg (meshes) and
labels.nrrd, byte for byte, as the exhaustive search's (issue 14: "same
answer"). A model that skelseg refuses or fails on (a flat mesh, a broken
file) gets a row saying so and the others still run; the exit code is then 1.
"""
import argparse, json, os, statistics, subprocess, sys, time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from invariance import rand_index_error, read_labels  # noqa: E402  (one Rand Index)

REPO = Path(__file__).resolve().parent.parent
TARGETS = {256: 5.0, 400: 20.0}  # seconds of wall time (issue 4)
MEMORY_TARGET_GB = 2.0
MESH_SUFFIXES = {".obj", ".off", ".stl", ".ply"}
COMPARED = ("skeleton.ply", "cuts.ply", "segmentation.seg", "labels.nrrd")


class RunFailed(RuntimeError):
    """skelseg exited non-zero on one model; the message names it and says why."""


def same_outputs(band, exhaustive):
    """Per output of COMPARED that either run wrote: whether both wrote it
    byte for byte alike; and the Rand Index error between the face labels."""
    files = {}
    for name in COMPARED:
        present = [(band / name).exists(), (exhaustive / name).exists()]
        if any(present):
            files[name] = all(present) and (band / name).read_bytes() == (exhaustive / name).read_bytes()
    seg = [band / "segmentation.seg", exhaustive / "segmentation.seg"]
    ri = 0.0
    if all(p.exists() for p in seg) and not files["segmentation.seg"]:
        labels = [read_labels(p) for p in seg]
        ri = rand_index_error(*labels) if labels[0].size == labels[1].size else 1.0
    return files, ri


def run_once(skelseg, mesh, resolution, threads, out, extra=()):
    if out.exists():
        subprocess.run(["rm", "-rf", str(out)], check=True)
    cmd = [str(skelseg), "segment", str(mesh), "-o", str(out), "--resolution", str(resolution), "-q"]
    if threads:
        cmd += ["--threads", str(threads)]
    cmd += list(extra)
    start = time.monotonic()
    proc = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        # /usr/bin/time adds "Command exited with non-zero status N" and the peak.
        said = [line for line in proc.stderr.strip().splitlines()
                if not line.strip().isdigit() and not line.startswith("Command exited with")]
        raise RunFailed(f"exit {proc.returncode}: {said[-1] if said else 'no message'}")
    peak_kb = int(proc.stderr.strip().splitlines()[-1])
    report = json.loads((out / "report.json").read_text())
    return {
        "wall": wall,
        "cpu": report["timing"]["cpu_seconds"],
        "serial_share": report["timing"]["serial_share"],
        "peak_gb": peak_kb / 1024 / 1024,
        "segments": report["segment_count"],
        "stages": {s["name"]: s["wall_seconds"] for s in report["stages"]},
        "path_set_share": sum(s["wall_seconds"] for s in report["stages"]
                              if s["name"] == "path sets, rims, areas, sigma") / max(wall, 1e-9),
        "nodes_settled": report["work"]["nodes_settled"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"))
    ap.add_argument("--data", default=str(REPO.parent / "shared" / "data"))
    ap.add_argument("--resolutions", default="256,400")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0, help="passed as --threads (default: all cores)")
    ap.add_argument("--out", default=str(REPO / "out" / "reference"))
    ap.add_argument("--models", default="armadillo.obj,hand.off",
                    help="file names in DATA/shapes, comma-separated, or 'all'")
    ap.add_argument("--compare-exhaustive", action="store_true",
                    help="run each model with the band search (the default) and, alternating in "
                         "the same session, with the exhaustive search, and add the comparison "
                         "columns: times, work and whether the outputs are the same (without "
                         "this flag: the band search only)")
    args = ap.parse_args()
    shapes = Path(args.data) / "shapes"
    if not shapes.is_dir():
        print(f"reference_runs: {shapes}: no such folder; skipping.")
        return 0
    meshes = (sorted(p for p in shapes.iterdir() if p.is_file() and p.suffix.lower() in MESH_SUFFIXES)
              if args.models == "all" else [shapes / m for m in args.models.split(",") if m])
    missing = [m.name for m in meshes if not m.is_file()]
    if missing or not meshes:
        print(f"reference_runs: {shapes} lacks {', '.join(missing) or 'any mesh'}; skipping.")
        return 0
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    resolutions = [int(r) for r in args.resolutions.split(",")]
    rows, record, failed = [], [], 0
    load_before = os.getloadavg()[0]
    for mesh in meshes:
        for resolution in resolutions:
            runs, exhaustive = [], []
            band_out = out / f"{mesh.stem}-{resolution}"
            exhaustive_out = out / f"{mesh.stem}-{resolution}-exhaustive"
            try:
                for _ in range(args.repeat):
                    band = ["--skeleton-search", "band"] if args.compare_exhaustive else []
                    runs.append(run_once(args.skelseg, mesh, resolution, args.threads, band_out, band))
                    if args.compare_exhaustive:
                        exhaustive.append(run_once(args.skelseg, mesh, resolution, args.threads,
                                                   exhaustive_out, ["--skeleton-search", "exhaustive"]))
            except RunFailed as failure:
                failed += 1
                record.append({"mesh": mesh.name, "resolution": resolution, "failed": str(failure)})
                rows.append(f"| {mesh.name} | {resolution} | failed: {failure} |")
                print(f"reference_runs: {mesh.name} at {resolution}: failed: {failure}", file=sys.stderr)
                continue
            med = {k: statistics.median(r[k] for r in runs) for k in ("wall", "cpu", "serial_share", "peak_gb")}
            record.append({"mesh": mesh.name, "resolution": resolution, "runs": runs, "median": med,
                           "exhaustive_runs": exhaustive})
            compare = ""
            if exhaustive:
                ew = statistics.median(r["wall"] for r in exhaustive)
                ec = statistics.median(r["cpu"] for r in exhaustive)
                files, ri = same_outputs(band_out, exhaustive_out)
                record[-1]["same_outputs"] = files
                record[-1]["ri_error"] = ri
                differ = [name for name, same in files.items() if not same]
                verdict_files = ("identical" if not differ else
                                 f"differ: {', '.join(differ)}; parts {runs[-1]['segments']} / "
                                 f"{exhaustive[-1]['segments']}; RI error {ri:.4f}")
                compare = (f" {statistics.median(r['path_set_share'] for r in runs) * 100:.0f}% | "
                           f"{ew:.2f} / {ec:.2f} | {statistics.median(r['path_set_share'] for r in exhaustive) * 100:.0f}% | "
                           f"{runs[0]['nodes_settled'] / max(exhaustive[0]['nodes_settled'], 1):.2f} | {verdict_files} |")
            target = TARGETS.get(resolution)
            verdict = "" if target is None else ("met" if med["wall"] <= target else f"not met ({med['wall'] / target:.1f}x)")
            rows.append(f"| {mesh.name} | {resolution} | {med['wall']:.2f} | "
                        f"{min(r['wall'] for r in runs):.2f} to {max(r['wall'] for r in runs):.2f} | {med['cpu']:.2f} | "
                        f"{med['serial_share'] * 100:.1f}% | {med['peak_gb']:.2f} | {runs[0]['segments']} | "
                        f"{'<= %g s: %s' % (target, verdict) if target else ''} |" + compare)
    (out / "reference.json").write_text(json.dumps(record, indent=2) + "\n")
    print(f"{args.repeat} runs each, {os.cpu_count()} vCPUs, 1-minute load average {load_before:.2f} before "
          f"and {os.getloadavg()[0]:.2f} after (our own runs add about 2); medians.\n")
    head = "| model | resolution | wall s (median) | wall s (range) | CPU s | serial share | peak GB | segments | target |"
    rule = "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | --- |"
    if args.compare_exhaustive:
        head += (" path-set share | exhaustive wall / CPU s | exhaustive path-set share | nodes settled, "
                 "band / exhaustive | outputs, band against exhaustive |")
        rule += " ---: | --- | ---: | ---: | --- |"
    print(head)
    print(rule)
    print("\n".join(rows))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
