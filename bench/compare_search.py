#!/usr/bin/python3
"""The band search (the default, --skeleton-search band) against the exhaustive search
(--skeleton-search exhaustive), issue 14: same curve skeleton, cuts and labels, and the work each one does.

Usage: bench/compare_search.py INPUT... [--skelseg build/skelseg]
                               [--resolution 192] [--threads N] [--out out/compare]
                               [--extra "--tau 1%"]
Each input is segmented both ways in the same session, one after the other.
Prints a Markdown table: whether skeleton.ply, cuts.ply and labels.nrrd are
byte-identical, the Rand Index error between the two face labellings
(meshes), the part counts, candidates measured, nodes settled and the CPU
seconds of the path-set stage of each. Writes OUT/compare.json. CPU seconds
and the work counters are the comparison to read on a loaded machine; wall
seconds are printed for completeness. An input that skelseg refuses both
ways with the same exit code (a flat mesh, a broken file) is the same
answer and is listed as refused by both; one that fails only one way, or
with different codes, is a difference. Either way the other inputs are still
compared. Exit code 1 when any input's answers differ beyond issue 14's
tolerance (Rand Index error 0.005, equal part counts) or fail unlike.
"""
import argparse, json, os, statistics, subprocess, sys, time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from invariance import rand_index_error, read_labels  # noqa: E402  (one Rand Index)

REPO = Path(__file__).resolve().parent.parent
STAGE = "path sets, rims, areas, sigma"


def read_run(out, wall):
    report = json.loads((out / "report.json").read_text())
    stage = [s for s in report["stages"] if s["name"] == STAGE]
    return {
        "wall": wall,
        "cpu": report["timing"]["cpu_seconds"],
        "stage_cpu": sum(s["cpu_seconds"] for s in stage),
        "stage_wall": sum(s["wall_seconds"] for s in stage),
        "parts": report["segment_count"],
        "candidates": report["counts"]["candidates"],
        "measured": report["work"]["candidates_measured"],
        "nodes_settled": report["work"]["nodes_settled"],
        "skeleton_points": report["counts"]["skeleton_points"],
        "coarse_candidates": report["work"].get("coarse_candidates", 0),
        "coarse_measured": report["work"].get("coarse_candidates_measured", 0),
        "thin_wall_seeds": report["work"].get("thin_wall_seeds", 0),
    }


class RunFailed(RuntimeError):
    """skelseg exited non-zero; `code` is its exit code, the message says why."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def last_line(text):
    lines = text.strip().splitlines()
    return lines[-1] if lines else "no message"


def run(skelseg, inp, out, resolution, threads, extra, exhaustive, reuse):
    if reuse:
        return read_run(out, 0.0)
    cmd = [str(skelseg), "segment", str(inp), "-o", str(out), "-q", "--no-preview", "--force",
           "--resolution", str(resolution)] + extra
    if threads:
        cmd += ["--threads", str(threads)]
    cmd += ["--skeleton-search", "exhaustive" if exhaustive else "band"]
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        raise RunFailed(proc.returncode, f"exit {proc.returncode}: {last_line(proc.stderr)}")
    return read_run(out, wall)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"))
    ap.add_argument("--resolution", type=int, default=192)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--extra", default="", help="more options for both runs, e.g. '--tau 1%%'")
    ap.add_argument("--out", default=str(REPO / "out" / "compare"))
    ap.add_argument("--reuse", action="store_true", help="tabulate the runs already in OUT")
    ap.add_argument("--reuse-exhaustive", action="store_true",
                    help="run only the band; reuse the exhaustive runs already in OUT (for trying "
                         "band options; CPU seconds are then not from the same session)")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    print("| input | resolution | skeleton.ply | cuts.ply | labels | RI error | parts (band / exhaustive) | "
          "C_tau points (band / exhaustive) | candidates | measured (band) | thin-wall seeds | coarse candidates measured / all | nodes settled (band / exhaustive) | "
          "path-set CPU s (band / exhaustive) | CPU s (band / exhaustive) |")
    print("| --- | ---: | --- | --- | --- | ---: | --- | --- | ---: | ---: | ---: | --- | --- | --- | --- |")
    for inp in map(Path, args.inputs):
        name = inp.stem
        runs, failures = {}, {}
        for mode in ("band", "exhaustive"):
            try:
                runs[mode] = run(args.skelseg, inp, out / f"{name}-{mode}", args.resolution,
                                 args.threads, args.extra.split(), mode == "exhaustive",
                                 args.reuse or (args.reuse_exhaustive and mode == "exhaustive"
                                                and (out / f"{name}-exhaustive" / "report.json").exists()))
            except RunFailed as failure:
                failures[mode] = failure
        if failures:
            alike = len(failures) == 2 and failures["band"].code == failures["exhaustive"].code
            said = "; ".join(f"{mode} {failure}" for mode, failure in failures.items())
            rows.append({"input": str(inp), "resolution": args.resolution, "identical": alike,
                         "refused_by_both": alike, "failed": {m: str(f) for m, f in failures.items()}})
            print(f"| {inp.name} | {args.resolution} | "
                  f"{'refused by both' if alike else 'FAILED'}: {said} |", flush=True)
            continue
        files = {f: (out / f"{name}-band" / f).read_bytes() == (out / f"{name}-exhaustive" / f).read_bytes()
                 for f in ("skeleton.ply", "cuts.ply", "labels.nrrd")}
        same = all(files.values())
        word = lambda f: "same" if files[f] else "DIFFER"
        seg_band, seg_exh = out / f"{name}-band" / "segmentation.seg", out / f"{name}-exhaustive" / "segmentation.seg"
        ri = rand_index_error(read_labels(seg_band), read_labels(seg_exh)) if seg_band.exists() else 0.0
        b, e = runs["band"], runs["exhaustive"]
        row = {"input": str(inp), "resolution": args.resolution, "identical": same, "files": files, "ri_error": ri,
               "band": b, "exhaustive": e}
        rows.append(row)
        print(f"| {inp.name} | {args.resolution} | {word('skeleton.ply')} | {word('cuts.ply')} | "
              f"{word('labels.nrrd')} | {ri:.4f} | {b['parts']} / {e['parts']} | "
              f"{b['skeleton_points']} / {e['skeleton_points']} | {b['candidates']} | {b['measured']} "
              f"({100.0 * b['measured'] / max(b['candidates'], 1):.0f}%) | {b['thin_wall_seeds']} | "
              f"{b['coarse_measured']} / {b['coarse_candidates']} | "
              f"{b['nodes_settled']} / {e['nodes_settled']} | {b['stage_cpu']:.2f} / {e['stage_cpu']:.2f} | "
              f"{b['cpu']:.2f} / {e['cpu']:.2f} |", flush=True)
    (out / "compare.json").write_text(json.dumps(rows, indent=1))
    failed = [r for r in rows if "failed" in r]
    bad = [r for r in failed if not r["refused_by_both"]]
    rows = [r for r in rows if "failed" not in r]
    bad += [r for r in rows if not r["identical"] and (r["ri_error"] > 0.005 or r["band"]["parts"] != r["exhaustive"]["parts"])]
    identical = sum(r["identical"] for r in rows)
    labels = sum(r["files"]["labels.nrrd"] and r["files"]["cuts.ply"] for r in rows)
    refused = len(failed) - sum(not r["refused_by_both"] for r in failed)
    refusals = f"; {refused} refused by both" if refused else ""
    if not rows:
        print(f"\nnone of {len(failed)} compared{refusals}; {len(bad)} failed one way only")
        return 1 if bad else 0
    ratio = lambda key: statistics.median(r["band"][key] / max(r["exhaustive"][key], 1e-9) for r in rows)
    print(f"\nmedian ratios band / exhaustive: path-set CPU s {ratio('stage_cpu'):.2f}, "
          f"CPU s {ratio('cpu'):.2f}, nodes settled {ratio('nodes_settled'):.2f}, "
          f"candidates measured {statistics.median(r['band']['measured'] / max(r['band']['candidates'], 1) for r in rows):.2f}; "
          f"summed path-set CPU s {sum(r['band']['stage_cpu'] for r in rows):.1f} / "
          f"{sum(r['exhaustive']['stage_cpu'] for r in rows):.1f}; 1-minute load average {os.getloadavg()[0]:.1f}")
    print(f"\n{identical} of {len(rows)} byte-identical in all three files, {labels} in cuts and labels{refusals}; "
          f"{len(bad)} outside RI error 0.005, with other part counts or failing one way only")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
