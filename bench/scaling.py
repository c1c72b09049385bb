#!/usr/bin/python3
"""Cost growth: stage times of skelseg at several resolutions.

Usage: bench/scaling.py [--skelseg build/skelseg] [--resolutions 64,128,256,400]
                        [--out out/scaling] MESH [MESH ...]
Runs `skelseg segment MESH --resolution R` for every mesh and resolution,
collects report.json, prints a Markdown table (wall seconds per stage group)
with the fitted exponent of wall time against resolution, and writes a
log-log plot to OUT/scaling.png.
"""
import argparse, json, math, os, subprocess, sys

GROUPS = {
    "read, checks, genus": ["read mesh", "check mesh", "genus", "genus with thin parts filled"],
    "voxelise": ["voxelise", "voxelise with thin parts filled"],
    "feature transform": ["feature transform"],
    "graph + candidates": ["boundary graph", "skeleton candidates", "landmarks", "objects", "crop"],
    "path sets, rims, areas, sigma": ["path sets, rims, areas, sigma"],
    "graph stages": ["skeleton graph", "cut placement", "labelling", "interior labels", "label volume"],
    "outputs": ["face labels", "write labels.nrrd", "write labels.vdb", "write skeleton.ply, cuts.ply",
                "segment surfaces and preview"],
}


def fit_exponent(xs, ys):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if y > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    num = sum((p[0] - mx) * (p[1] - my) for p in pts)
    den = sum((p[0] - mx) ** 2 for p in pts)
    return num / den if den else float("nan")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("meshes", nargs="+")
    ap.add_argument("--skelseg", default="build/skelseg")
    ap.add_argument("--resolutions", default="64,128,256,400")
    ap.add_argument("--out", default="out/scaling")
    args = ap.parse_args()
    resolutions = [int(r) for r in args.resolutions.split(",")]
    results = {}
    for mesh in args.meshes:
        name = os.path.splitext(os.path.basename(mesh))[0]
        for r in resolutions:
            outdir = os.path.join(args.out, f"{name}-{r}")
            subprocess.run([args.skelseg, "segment", mesh, "-o", outdir, "--resolution", str(r), "-q", "--force"],
                           check=True)
            with open(os.path.join(outdir, "report.json")) as f:
                results[(name, r)] = json.load(f)
            rep = results[(name, r)]
            print(f"{name} {r}: {rep['timing']['wall_seconds']:.2f} s, {rep['segment_count']} segments, "
                  f"peak {rep['memory']['peak_resident_bytes'] / 1e9:.2f} GB", file=sys.stderr)
    with open(os.path.join(args.out, "scaling.json"), "w") as f:
        json.dump({f"{k[0]}-{k[1]}": v for k, v in results.items()}, f, indent=1)
    names = sorted({k[0] for k in results})
    print("| model | resolution | " + " | ".join(GROUPS) + " | total wall | CPU | serial share | peak GB | parts |")
    print("| --- | ---: | " + " | ".join("---:" for _ in GROUPS) + " | ---: | ---: | ---: | ---: | ---: |")
    series = {}
    for name in names:
        for r in resolutions:
            rep = results[(name, r)]
            stages = {s["name"]: s["wall_seconds"] for s in rep["stages"]}
            cells = []
            for group, members in GROUPS.items():
                t = sum(stages.get(m, 0.0) for m in members)
                series.setdefault((name, group), []).append(t)
                cells.append(f"{t:.2f}")
            total = rep["timing"]["wall_seconds"]
            series.setdefault((name, "total"), []).append(total)
            print(f"| {name} | {r} | " + " | ".join(cells) +
                  f" | {total:.2f} | {rep['timing']['cpu_seconds']:.2f} | {100 * rep['timing']['serial_share']:.1f}% |"
                  f" {rep['memory']['peak_resident_bytes'] / 1e9:.2f} | {rep['segment_count']} |")
    print("\nFitted exponent of wall time against resolution (log-log least squares, all resolutions):\n")
    print("| model | " + " | ".join(list(GROUPS) + ["total"]) + " |")
    print("| --- | " + " | ".join("---:" for _ in range(len(GROUPS) + 1)) + " |")
    for name in names:
        print(f"| {name} | " + " | ".join(f"{fit_exponent(resolutions, series[(name, g)]):.2f}"
                                          for g in list(GROUPS) + ["total"]) + " |")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, len(names), figsize=(6 * len(names), 4.5), squeeze=False)
        for ax, name in zip(axes[0], names):
            for g in list(GROUPS) + ["total"]:
                ax.loglog(resolutions, [max(t, 1e-3) for t in series[(name, g)]], marker="o", label=g,
                          linewidth=2.5 if g == "total" else 1.2)
            ax.set_title(name)
            ax.set_xlabel("resolution (voxels along the longest side)")
            ax.set_ylabel("wall seconds")
            ax.grid(True, which="both", alpha=0.3)
        axes[0][0].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "scaling.png"), dpi=90)
    except ImportError:
        print("matplotlib missing: no plot", file=sys.stderr)


if __name__ == "__main__":
    main()
