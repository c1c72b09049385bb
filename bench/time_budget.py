#!/usr/bin/python3
"""The --time-budget table of issue 14: every input at each budget, the
share of runs that finish within the budget and the resolution chosen.

Usage: bench/time_budget.py INPUT... [--skelseg build/skelseg]
                            [--budgets 1,2,5] [--resolution 400] [--threads N]
                            [--out out/budget] [--extra "--exhaustive"]
Each run is `skelseg segment INPUT --time-budget B --resolution R` with all
outputs; wall time is measured around the process. A run counts as within
budget when it exits 0 and its wall time is at most B; the table also
counts runs whose CPU seconds are at most B (the model predicts CPU
seconds, which a loaded machine inflates less than wall seconds). Runs that stop
(exit 3: nothing fitted, the budget acted as --time-limit) count as not
within budget. Prints a Markdown table per budget (with the share of the
budget the finished runs used) and one row per run in OUT/budget.json
(with report.json's calibration: bench/fit_budget_calibration.py fits it). The 1-minute load average is printed at the start and the
end (the machine is shared: repeat a table measured under a load over 3).
"""
import argparse, json, os, statistics, subprocess, sys, time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"))
    ap.add_argument("--budgets", default="1,2,5")
    ap.add_argument("--resolution", type=int, default=400)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", default=str(REPO / "out" / "budget"))
    ap.add_argument("--extra", default="", help="more options for every run, e.g. '--exhaustive'")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    load_start = os.getloadavg()[0]
    for budget in map(float, args.budgets.split(",")):
        for inp in map(Path, args.inputs):
            d = out / f"{inp.stem}-{budget:g}"
            cmd = [args.skelseg, "segment", str(inp), "-o", str(d), "-q", "--force",
                   "--resolution", str(args.resolution), "--time-budget", str(budget)]
            if args.threads:
                cmd += ["--threads", str(args.threads)]
            cmd += args.extra.split()
            start = time.monotonic()
            proc = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.monotonic() - start
            row = {"input": inp.name, "budget": budget, "exit": proc.returncode, "wall": wall}
            if proc.returncode == 0:
                rep = json.loads((d / "report.json").read_text())
                tb = rep["time_budget"]
                row["cpu"] = rep["timing"]["cpu_seconds"]
                row.update(resolution=tb["resolution"], coarsening=tb["coarsening"],
                           predicted=tb["predicted_seconds"], probe=tb["probe_seconds"], fits=tb["fits"],
                           skipped=tb.get("skipped", []),
                           predicted_cpu=tb.get("predicted_cpu_seconds", tb["predicted_seconds"]),
                           calibration=tb.get("calibration"))
                refinement = tb.get("refinement") or {}
                row.update(finer_tried=bool(refinement.get("tried")),
                           finer_kept=bool(refinement.get("kept")),
                           first_resolution=(refinement.get("first_resolution")))
            rows.append(row)
            print(f"{inp.name} budget {budget:g}: exit {proc.returncode}, {wall:.2f} s, "
                  f"resolution {row.get('resolution')}, predicted {row.get('predicted', 0):.2f}",
                  file=sys.stderr, flush=True)
    (out / "budget.json").write_text(json.dumps(rows, indent=1))
    print(f"1-minute load average: {load_start:.1f} at the start, {os.getloadavg()[0]:.1f} at the end\n")
    print("| budget s | runs | within budget (wall) | within budget (CPU s) | stopped (exit 3) | "
          "resolution chosen (median, range) | wall s (median, worst) | CPU s (median, worst) | predicted s (median) | "
          "preview skipped | budget used (median, worst) | finer pass kept / tried |")
    print("| ---: | ---: | ---: | ---: | ---: | --- | --- | --- | ---: | ---: | --- | ---: |")
    for budget in map(float, args.budgets.split(",")):
        rs = [r for r in rows if r["budget"] == budget]
        ok = [r for r in rs if r["exit"] == 0 and r["wall"] <= budget]
        stopped = [r for r in rs if r["exit"] == 3]
        ok_cpu = [r for r in rs if r["exit"] == 0 and r["cpu"] <= budget]
        cpus = [r["cpu"] for r in rs if "cpu" in r] or [0.0]
        res = [r["resolution"] for r in rs if r.get("resolution")]
        walls = [r["wall"] for r in rs]
        pred = [r["predicted"] for r in rs if "predicted" in r]
        # Of the runs that finished: the share of the budget a user got used.
        used = [r["wall"] / budget for r in rs if r["exit"] == 0] or [0.0]
        res_text = f"{statistics.median(res):.0f} ({min(res)} to {max(res)})" if res else "-"
        print(f"| {budget:g} | {len(rs)} | {len(ok)} ({100.0 * len(ok) / max(len(rs), 1):.0f}%) | "
              f"{len(ok_cpu)} ({100.0 * len(ok_cpu) / max(len(rs), 1):.0f}%) | "
              f"{len(stopped)} | {res_text} | {statistics.median(walls):.2f}, {max(walls):.2f} | "
              f"{statistics.median(cpus):.2f}, {max(cpus):.2f} | "
              f"{statistics.median(pred) if pred else 0:.2f} | "
              f"{sum(1 for r in rs if r.get('skipped'))} | "
              f"{100.0 * statistics.median(used):.0f}%, {100.0 * max(used):.0f}% | "
              f"{sum(1 for r in rs if r.get('finer_kept'))} / "
              f"{sum(1 for r in rs if r.get('finer_tried'))} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
