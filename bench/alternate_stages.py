#!/usr/bin/python3
"""Stage table of two (or more) skelseg binaries, runs alternated.

Runs `skelseg segment MESH --resolution R --threads T --force -q` with each
binary in turn, RUNS times, and prints the median wall / CPU seconds of every
stage of report.json, the run's total, the peak memory and the load average
before each run (other users of the machine disturb wall times more than CPU
seconds; quote both). Alternating the binaries in one session spreads the
load over both.

Example (docs/performance.md, "Stages outside the skeleton search at 400"):
    bench/alternate_stages.py /tmp/before/skelseg build/skelseg \\
        --mesh ../shared/data/shapes/armadillo.obj --resolution 400 --runs 3
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("binaries", nargs="+", help="skelseg executables to compare")
    shared = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared")
    parser.add_argument("--mesh", default=os.path.join(shared, "data", "shapes", "armadillo.obj"),
                        help="input mesh or volume (default: the shared armadillo.obj)")
    parser.add_argument("--resolution", type=int, default=400)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--json", help="also write every run's figures here")
    args = parser.parse_args()
    results = {b: [] for b in args.binaries}
    with tempfile.TemporaryDirectory(prefix="alternate_stages") as scratch:
        for run in range(args.runs):
            for index, binary in enumerate(args.binaries):
                load = os.getloadavg()[0]
                out = os.path.join(scratch, str(index))
                subprocess.run([binary, "segment", args.mesh, "-o", out, "--resolution",
                                str(args.resolution), "--threads", str(args.threads), "--force",
                                "-q"], check=True)
                with open(os.path.join(out, "report.json")) as f:
                    report = json.load(f)
                results[binary].append({
                    "load": load,
                    "wall": report["timing"]["wall_seconds"],
                    "cpu": report["timing"]["cpu_seconds"],
                    "peak": report["memory"]["peak_resident_bytes"],
                    "stages": {s["name"]: [s["wall_seconds"], s["cpu_seconds"]]
                               for s in report["stages"]}})
                print(f"{binary} run {run}: load {load:.2f}, wall {results[binary][-1]['wall']:.2f} s,"
                      f" CPU {results[binary][-1]['cpu']:.2f} s", file=sys.stderr, flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    names = []
    for runs in results.values():
        for r in runs:
            names += [n for n in r["stages"] if n not in names]
    print("| stage | " + " | ".join(f"{b} wall / CPU s" for b in args.binaries) + " |")
    print("|---|" + "---|" * len(args.binaries))

    def median(values):
        return statistics.median(values)

    for name in names + ["whole run"]:
        cells = []
        for binary in args.binaries:
            runs = results[binary]
            if name == "whole run":
                wall, cpu = median([r["wall"] for r in runs]), median([r["cpu"] for r in runs])
            else:
                wall = median([r["stages"].get(name, [0, 0])[0] for r in runs])
                cpu = median([r["stages"].get(name, [0, 0])[1] for r in runs])
            cells.append(f"{wall:.3f} / {cpu:.3f}")
        print(f"| {name} | " + " | ".join(cells) + " |")
    for binary in args.binaries:
        runs = results[binary]
        print(f"{binary}: peak {median([r['peak'] for r in runs]) / 1e6:.0f} MB, load averages "
              + ", ".join(f"{r['load']:.2f}" for r in runs))


if __name__ == "__main__":
    main()
