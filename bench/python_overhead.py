#!/usr/bin/env python3
"""The cost of calling the engine from Python against running the CLI.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py
           [--binary build/skelseg] [--size 256] [--runs 3] [--threads N]

Generates `skelseg generate figure --size SIZE --pose 1`, then alternates
`skelseg segment FILE -o DIR -q --no-preview --force` (a process: read,
segment, write every output) and `skelseg.segment(read_volume(FILE))` (in
this process: array in, arrays out), RUNS times each, and prints the median
wall time of each, the median time both spent in the engine's segmentation
stages (from their reports), and what each spent outside them.
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import skelseg

# Stages the CLI runs around the engine (reading, writing): not segmentation.
CLI_ONLY = ("read", "write", "segment surfaces")


def engine_seconds(report: dict) -> float:
    return sum(s["wall_seconds"] for s in report["stages"]
               if not s["name"].startswith(CLI_ONLY))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="build/skelseg")
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--threads", type=int, default=None)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        shape = pathlib.Path(tmp) / "figure.nrrd"
        subprocess.run([args.binary, "generate", "figure", "-o", shape, "--size", str(args.size),
                        "--pose", "1"], check=True, capture_output=True)
        threads = [] if args.threads is None else ["--threads", str(args.threads)]
        cli_wall, cli_engine, py_wall, py_engine = [], [], [], []
        for run in range(args.runs):
            out = pathlib.Path(tmp) / f"out{run}"
            start = time.perf_counter()
            subprocess.run([args.binary, "segment", shape, "-o", out, "-q", "--no-preview",
                            "--force", *threads], check=True)
            cli_wall.append(time.perf_counter() - start)
            cli_engine.append(engine_seconds(json.loads((out / "report.json").read_text())))

            start = time.perf_counter()
            result = skelseg.segment(skelseg.read_volume(shape), threads=args.threads)
            py_wall.append(time.perf_counter() - start)
            py_engine.append(engine_seconds(result.report))
    median = statistics.median
    print(f"figure {args.size}^3, {args.runs} runs each, alternating; medians:")
    print(f"  CLI    process wall {median(cli_wall):7.3f} s, segmentation stages "
          f"{median(cli_engine):7.3f} s, outside them {median(cli_wall) - median(cli_engine):6.3f} s")
    print(f"  Python call wall    {median(py_wall):7.3f} s, segmentation stages "
          f"{median(py_engine):7.3f} s, outside them {median(py_wall) - median(py_engine):6.3f} s")
    print(f"  Python / CLI wall: {median(py_wall) / median(cli_wall):.3f}")
    print(f"  all runs: CLI {[round(t, 3) for t in cli_wall]}, Python {[round(t, 3) for t in py_wall]}")


if __name__ == "__main__":
    main()
