#!/usr/bin/python3
"""Fits the cost model of `--time-budget` (engine/TimeBudget.h) from measured
runs: wall seconds of `skelseg segment` (all outputs, default band search)
against the work counters of report.json.

Usage: bench/fit_cost_model.py MESH... [--skelseg build/skelseg]
                               [--resolutions 96,128,192,256] [--threads N]
                               [--out out/costmodel] [--reuse]
Model (of CPU seconds by default, see --target): seconds = c0 + c1*grid voxels + c2*object voxels
              + c3*candidates*sqrt(boundary voxels) + c4*mesh faces,
fitted by non-negative least squares on the run's seconds without
preview.png; the preview is fitted on its own (seconds = p0 + p1*mesh
triangles, from the stage "segment surfaces and preview" less its
"write segments.glb, viewer.html"), since the engine may skip it under a
budget. The safety margin (CostModel::safetyMargin) is the 90th percentile
of the leave-one-mesh-out under-prediction (actual / predicted - 1).
CPU seconds are the default target
because wall seconds on a shared machine under load say more about the load
than about the run; on an idle 2-vCPU machine a run's wall time is about its
CPU time divided by 1.9, so a budget checked against CPU seconds is
conservative there. Fitted on relative error (each run weighs
1/wall), and the growth exponent of the candidates with the resolution
(median over the meshes of the log-log slope). Prints the coefficients as
C++ for CostModel::fitted() and the fit error (median and worst relative
error, and the same with each mesh left out of the fit). --reuse fits the
runs already in OUT (their report.json) instead of running again.
"""
import argparse, json, statistics, subprocess, sys, time
from pathlib import Path

import numpy as np
from scipy.optimize import nnls

REPO = Path(__file__).resolve().parent.parent


def features(r):
    return [1.0, r["grid"], r["objects"], r["candidates"] * r["boundary"] ** 0.5, r["faces"]]


TARGET = "cpu"


def preview_seconds(r):
    stages = r.get("stages", {})
    return max(0.0, stages.get("segment surfaces and preview", 0.0)
               - stages.get("write segments.glb, viewer.html", 0.0))


def run_seconds(r):
    """The target without preview.png (wall: its stage wall; CPU: its stage CPU)."""
    key = "preview_cpu" if TARGET == "cpu" else "preview_wall"
    return r[TARGET] - r.get(key, 0.0)


def stage_table(rep, field):
    table = {}
    for s in rep.get("stages", []):
        table[s["name"]] = table.get(s["name"], 0.0) + s[field]
    return table


def run_record(mesh, res, wall, rep):
    g = rep["grid"]["size"]
    r = {"mesh": mesh, "resolution": res, "wall": wall, "cpu": rep["timing"]["cpu_seconds"],
         "grid": float(g[0] * g[1] * g[2]),
         "objects": float(rep["counts"]["object_voxels"]),
         "boundary": float(rep["counts"]["boundary_voxels"]),
         "candidates": float(rep["counts"]["candidates"]),
         "faces": float(rep["input"].get("faces", 0)),
         "stages": stage_table(rep, "wall_seconds")}
    r["preview_wall"] = preview_seconds(r)
    cpu_stages = stage_table(rep, "cpu_seconds")
    r["preview_cpu"] = max(0.0, cpu_stages.get("segment surfaces and preview", 0.0)
                           - cpu_stages.get("write segments.glb, viewer.html", 0.0))
    return r


def fit(runs):
    a = np.array([features(r) for r in runs])
    y = np.array([run_seconds(r) for r in runs])
    w = 1.0 / y
    coef, _ = nnls(a * w[:, None], y * w)
    return coef


def predict(coef, r):
    return float(np.dot(coef, features(r)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("meshes", nargs="*")
    ap.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"))
    ap.add_argument("--resolutions", default="96,128,192,256")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", default=str(REPO / "out" / "costmodel"))
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--target", choices=("cpu", "wall"), default="cpu",
                    help="fit CPU seconds (default: robust to a loaded machine) or wall seconds")
    args = ap.parse_args()
    global TARGET
    TARGET = args.target
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    runs = []
    if args.reuse:
        # Process wall seconds from runs.json when it is there (report.json
        # has the engine's own, without process start and exit).
        walls = {}
        if (out / "runs.json").exists():
            walls = {(r["mesh"], r["resolution"]): r["wall"]
                     for r in json.loads((out / "runs.json").read_text())}
        for rep_path in sorted(out.glob("*/report.json")):
            rep = json.loads(rep_path.read_text())
            mesh = Path(rep["input"]["file"]).name
            res = rep["input"]["resolution"]
            wall = walls.get((mesh, res), rep["timing"]["wall_seconds"])
            runs.append(run_record(mesh, res, wall, rep))
    else:
        for mesh in map(Path, args.meshes):
            for res in map(int, args.resolutions.split(",")):
                d = out / f"{mesh.stem}-{res}"
                cmd = [args.skelseg, "segment", str(mesh), "-o", str(d), "-q", "--force",
                       "--resolution", str(res)]
                if args.threads:
                    cmd += ["--threads", str(args.threads)]
                start = time.monotonic()
                proc = subprocess.run(cmd, capture_output=True, text=True)
                wall = time.monotonic() - start
                if proc.returncode != 0:
                    print(f"fit_cost_model: {' '.join(cmd)} failed: {proc.stderr.strip()[-200:]}", file=sys.stderr)
                    continue
                rep = json.loads((d / "report.json").read_text())
                runs.append(run_record(mesh.name, res, wall, rep))
                print(f"{mesh.name} {res}: {wall:.2f} s", file=sys.stderr, flush=True)
        (out / "runs.json").write_text(json.dumps(runs, indent=1))
    coef = fit(runs)
    errors = [abs(predict(coef, r) - run_seconds(r)) / run_seconds(r) for r in runs]
    loo, under = [], []
    for m in sorted({r["mesh"] for r in runs}):
        c = fit([r for r in runs if r["mesh"] != m])
        for r in runs:
            if r["mesh"] == m:
                loo.append(abs(predict(c, r) - run_seconds(r)) / run_seconds(r))
                under.append(run_seconds(r) / predict(c, r) - 1.0)
    margin = max(0.0, float(np.percentile(under, 90)))
    # preview.png on its own: fixed + per triangle, least squares on relative error.
    key = "preview_cpu" if TARGET == "cpu" else "preview_wall"
    pv = [r for r in runs if r.get(key, 0.0) > 0]
    pcoef = [0.0, 0.0]
    if len(pv) >= 2:
        a = np.array([[1.0, r["faces"]] for r in pv]); y = np.array([r[key] for r in pv])
        pcoef, _ = nnls(a / y[:, None], np.ones(len(pv)))
    perr = [abs(pcoef[0] + pcoef[1] * r["faces"] - r[key]) / r[key] for r in pv] or [0.0]
    # The residual table of docs/performance.md: per run, actual / predicted.
    (out / "residuals.json").write_text(json.dumps(
        [{"mesh": r["mesh"], "resolution": r["resolution"], "actual": run_seconds(r),
          "predicted": predict(coef, r), "preview": r.get(key, 0.0)} for r in runs], indent=1))
    slopes = []
    for m in sorted({r["mesh"] for r in runs}):
        rs = sorted((r for r in runs if r["mesh"] == m), key=lambda r: r["resolution"])
        if len(rs) >= 2 and all(r["candidates"] > 0 for r in rs):
            x = np.log([r["resolution"] for r in rs]); y = np.log([r["candidates"] for r in rs])
            slopes.append(float(np.polyfit(x, y, 1)[0]))
    exponent = statistics.median(slopes) if slopes else 2.0
    print(f"runs: {len(runs)}")
    print("    m.seconds = %.3g;\n    m.perGridVoxel = %.3g;\n    m.perObjectVoxel = %.3g;\n"
          "    m.perCandidatePath = %.3g;\n    m.perMeshFace = %.3g;\n    m.candidateExponent = %.3g;\n"
          "    m.previewSeconds = %.3g;\n    m.previewPerTriangle = %.3g;\n    m.safetyMargin = %.2f;"
          % (coef[0], coef[1], coef[2], coef[3], coef[4], exponent, pcoef[0], pcoef[1], margin))
    print(f"preview.png: relative error median {statistics.median(perr):.1%}, worst {max(perr):.1%}")
    print(f"relative error: median {statistics.median(errors):.1%}, worst {max(errors):.1%}")
    print(f"leave one mesh out: median {statistics.median(loo):.1%}, worst {max(loo):.1%}")
    (out / "model.json").write_text(json.dumps({"coefficients": list(map(float, coef)),
                                                "candidate_exponent": exponent,
                                                "median_error": statistics.median(errors),
                                                "worst_error": max(errors),
                                                "loo_median_error": statistics.median(loo),
                                                "loo_worst_error": max(loo),
                                                "preview_coefficients": list(map(float, pcoef)),
                                                "safety_margin": margin}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
