#!/usr/bin/python3
"""Fits the probe calibration of `--time-budget` (engine/BudgetCalibration.h)
from the runs of bench/time_budget.py.

Usage: bench/fit_budget_calibration.py OUT... [--quantile 0.95] [--exclude-budgets 1]

OUT: output folders of bench/time_budget.py (budget.json and one folder per
run with its report.json). For every run that finished:
  - the probe's CPU seconds (stage "time budget probe") against its work:
    probe CPU = q0 + q1*mesh faces + q2*probe grid voxels + q3*probe object
    voxels, fitted by non-negative least squares on relative error
    (ProbeCostModel::seconds, perMeshFace, perGridVoxel, perObjectVoxel);
  - the run's wall seconds after the probe per CPU second that CostModel
    predicted for it (the preview's prediction included when it was written),
    against the probe's wall seconds per CPU second predicted for the probe:
    their median ratio is ProbeCostModel::runWallPerProbeWall;
  - the safety margin: the QUANTILE of (actual / calibrated prediction - 1).
Runs of main's build (before budget17) have no probe counters in
report.json: they are estimated from the run's grid and object voxels,
scaled to the probe resolution (64). The wall seconds after the probe are
the process's wall seconds (budget.json) less those before the probe ended.
Prints the coefficients as C++ for ProbeCostModel::fitted(), the spread of
the residuals, and what the margin would give: the share of runs whose
actual seconds after the probe stay within their calibrated prediction
times (1 + margin).
"""
import argparse, json, statistics, sys
from pathlib import Path

import numpy as np
from scipy.optimize import nnls

PROBE_RESOLUTION = 64


def stage(rep, name, field):
    return sum(s[field] for s in rep.get("stages", []) if s["name"] == name)


def record(row, rep):
    tb = rep["time_budget"]
    cal = tb.get("calibration") or {}
    k = cal.get("wall_per_cpu_second", 1.0)
    faces = float(rep["input"].get("faces", 0))
    if "probe_grid_voxels" in cal:
        grid, objects = cal["probe_grid_voxels"], cal["probe_object_voxels"]
    else:
        size = rep["grid"]["size"]
        scale = (min(PROBE_RESOLUTION, tb["requested_resolution"]) / tb["resolution"]) ** 3
        grid = float(size[0] * size[1] * size[2]) * scale
        objects = float(rep["counts"]["object_voxels"]) * scale
    if "seconds_left_after_probe" in tb:
        before = tb["budget_seconds"] - tb["seconds_left_after_probe"]
    else:
        # Process start and the stages up to the probe (the early stages run
        # one after the other).
        before = (row["wall"] - rep["timing"]["wall_seconds"]
                  + sum(stage(rep, n, "wall_seconds") for n in ("read mesh", "check mesh", "time budget probe")))
    predicted_cpu = tb.get("predicted_cpu_seconds", tb["predicted_seconds"])
    if not tb.get("skipped"):
        predicted_cpu += tb["preview_predicted_seconds"] / k
    return {"input": row["input"], "budget": row["budget"], "faces": faces, "grid": grid, "objects": objects,
            "probe_wall": tb["probe_seconds"], "probe_cpu": stage(rep, "time budget probe", "cpu_seconds"),
            "after": row["wall"] - before, "predicted_cpu": predicted_cpu, "resolution": tb["resolution"]}


def features(r):
    return [1.0, r["faces"], r["grid"], r["objects"]]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outs", nargs="+")
    ap.add_argument("--quantile", type=float, default=0.95)
    ap.add_argument("--exclude-budgets", default="", help="budgets to leave out of the fit, e.g. '1'")
    args = ap.parse_args()
    excluded = {float(b) for b in args.exclude_budgets.split(",") if b}
    runs = []
    for out in map(Path, args.outs):
        for row in json.loads((out / "budget.json").read_text()):
            if row["exit"] != 0 or row["budget"] in excluded:
                continue
            rep = json.loads((out / f"{Path(row['input']).stem}-{row['budget']:g}" / "report.json").read_text())
            if rep.get("input", {}).get("kind") != "mesh":
                continue
            runs.append(record(row, rep))
    if len(runs) < 5:
        print("too few finished mesh runs", file=sys.stderr)
        return 1
    a = np.array([features(r) for r in runs])
    y = np.array([r["probe_cpu"] for r in runs])
    coef, _ = nnls(a / y[:, None], np.ones(len(y)))
    probe_pred = a @ coef
    probe_err = np.abs(probe_pred / y - 1)
    run_ratio = np.array([r["after"] / r["predicted_cpu"] for r in runs])
    probe_ratio = np.array([r["probe_wall"] for r in runs]) / probe_pred
    alpha = float(np.median(run_ratio / probe_ratio))
    residual = run_ratio / (alpha * probe_ratio)
    margin = float(np.quantile(residual, args.quantile)) - 1.0
    print(f"{len(runs)} finished mesh runs from {len(set(r['input'] for r in runs))} meshes")
    print(f"probe CPU model: relative error median {100 * np.median(probe_err):.1f}%, worst {100 * probe_err.max():.1f}%")
    print(f"run wall per predicted CPU second: median {np.median(run_ratio):.2f} ({run_ratio.min():.2f} to {run_ratio.max():.2f})")
    print(f"probe wall per predicted CPU second: median {np.median(probe_ratio):.2f} ({probe_ratio.min():.2f} to {probe_ratio.max():.2f})")
    print(f"calibrated residual (actual / predicted): median {np.median(residual):.2f}, "
          f"90% {np.quantile(residual, 0.9):.2f}, 95% {np.quantile(residual, 0.95):.2f}, worst {residual.max():.2f}")
    uncal = run_ratio / np.median(run_ratio)
    print(f"for comparison, a constant factor (median): 90% {np.quantile(uncal, 0.9):.2f}, "
          f"95% {np.quantile(uncal, 0.95):.2f}, worst {uncal.max():.2f}")
    measured = np.array([r["probe_wall"] / r["probe_cpu"] for r in runs])
    by_cpu = run_ratio / measured
    by_cpu /= np.median(by_cpu)
    print(f"for comparison, the probe's wall per its measured CPU second: 90% {np.quantile(by_cpu, 0.9):.2f}, "
          f"95% {np.quantile(by_cpu, 0.95):.2f}, worst {by_cpu.max():.2f}")
    worst = sorted(zip(residual, runs), key=lambda t: -t[0])[:8]
    print("largest residuals: " + ", ".join(f"{r['input']} at {r['budget']:g} s ({v:.2f})" for v, r in worst))
    print("\n    m.seconds = %.3g;\n    m.perMeshFace = %.3g;\n    m.perGridVoxel = %.3g;\n"
          "    m.perObjectVoxel = %.3g;\n    m.runWallPerProbeWall = %.3g;\n    m.safetyMargin = %.2f;"
          % (coef[0], coef[1], coef[2], coef[3], alpha, margin))
    return 0


if __name__ == "__main__":
    sys.exit(main())
