#!/usr/bin/python3
"""Joint candidates against the human segmentations of the PSB models.

Reads the joint candidates that `skelseg segment --joints` lists in
OUT/N/report.json (every narrowing with ratio <= 0.95 and every bend of at
least 20 degrees, kept or not) for the models of a psb_benchmark.py output
folder, and asks for each whether people cut there: a candidate is "at a
human cut" when at least half of the model's human segmentations have a
segment boundary (a mesh edge between faces of different labels) within
1.5 local radii of the skeleton point (the loop around a limb lies about one
radius from its skeleton). It prints the distributions of the narrowing
ratios and bend angles at human cuts and elsewhere, and how many candidates
each threshold would keep and how many of those are at human cuts.

    /usr/bin/python3 bench/psb_benchmark.py --categories articulated \\
        --segment-args=--joints --out out/psb-joints
    /usr/bin/python3 bench/joint_candidates.py out/psb-joints

Needs numpy and scipy.
"""

import argparse
import gzip
import json
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

REPO = Path(__file__).resolve().parent.parent


def read_off(path):
    tokens = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                tokens.extend(line.split())
    if tokens[0] == "OFF":
        tokens = tokens[1:]
    nv, nf = int(tokens[0]), int(tokens[1])
    pos = 3
    vertices = np.array(tokens[pos:pos + 3 * nv], dtype=float).reshape(nv, 3)
    pos += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(tokens[pos])
        faces.append([int(t) for t in tokens[pos + 1:pos + 1 + k]])
        pos += 1 + k
    return vertices, faces


def read_labels(path):
    data = Path(path).read_bytes()
    if data[:2] == b"\x1f\x8b":
        data = gzip.decompress(data)
    return np.array([int(t) for t in data.split()])


def boundary_points(vertices, faces, labels):
    """Vertices of edges between faces of different labels."""
    edge_faces = {}
    for fi, face in enumerate(faces):
        for a, b in zip(face, face[1:] + face[:1]):
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(fi)
    points = set()
    for (a, b), fs in edge_faces.items():
        if len({int(labels[f]) for f in fs}) > 1:
            points.update((a, b))
    return vertices[sorted(points)] if points else np.zeros((0, 3))


def read_skeleton(path):
    """(x, y, z, rho_s) of every vertex of a skeleton.ply (binary, see docs/outputs.md)."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    count = int(header.split("element vertex ")[1].split()[0])
    vertex = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rho_s", "<f4"), ("rho_c", "<f4"),
                       ("sigma", "<f4"), ("junction", "u1"), ("critical", "u1")])
    v = np.frombuffer(data, dtype=vertex, count=count, offset=end)
    return np.stack([v["x"], v["y"], v["z"], v["rho_s"]], axis=1).astype(float)


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", help="psb_benchmark.py output folder (run with --segment-args=--joints)")
    p.add_argument("--data", default=str(REPO.parent / "shared" / "data"))
    p.add_argument("--reach", type=float, default=1.5, help="radii (default 1.5)")
    p.add_argument("--skip-near-cut", action="store_true",
                   help="leave out candidates within the distance rule of a junction-rule cut")
    args = p.parse_args(argv)
    psb = Path(args.data) / "psb"
    rows, base = [], []
    for report_path in sorted(Path(args.out).glob("*/report.json"), key=lambda q: int(q.parent.name)):
        model = int(report_path.parent.name)
        report = json.loads(report_path.read_text())
        candidates = report.get("joint_candidates", [])
        if not candidates:
            continue
        vertices, faces = read_off(psb / "off" / f"{model}.off")
        trees = []
        for seg in sorted((psb / "seg" / str(model)).glob("*.seg.gz")):
            pts = boundary_points(vertices, faces, read_labels(seg))
            if len(pts):
                trees.append(cKDTree(pts))
        voxel = report["grid"]["voxel_size"]
        # Base rate: the share of all skeleton points that are "at a human cut".
        skeleton = read_skeleton(report_path.parent / "skeleton.ply")
        for x, y, z, rho_s in skeleton:
            reach = args.reach * max(rho_s / np.pi, 0.5) * voxel  # rho_s in voxels
            near = sum(1 for t in trees if t.query((x, y, z))[0] <= reach)
            base.append(near * 2 >= max(len(trees), 1))
        for c in candidates:
            if args.skip_near_cut and c["status"] == "near_cut":
                continue
            reach = args.reach * c["radius"] * voxel
            near = sum(1 for t in trees if t.query(c["position"])[0] <= reach)
            rows.append({"model": model, "kind": c["kind"], "status": c["status"],
                         "ratio": c["ratio"], "angle": c["angle_degrees"], "sigma": c["sigma"],
                         "human": near * 2 >= max(len(trees), 1)})
    if not rows:
        print("no joint candidates found (was the benchmark run with --segment-args=--joints?)")
        return 0
    print(f"{len(rows)} candidates on {len({r['model'] for r in rows})} models; "
          f"{np.mean(base):.2f} of all {len(base)} skeleton points are at a human cut (base rate)")
    for kind, key, thresholds, keep in (
            ("narrowing", "ratio", [0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95], lambda v, t: v <= t),
            ("bend", "angle", [20, 30, 40, 45, 50, 60, 70, 80], lambda v, t: v >= t)):
        sel = [r for r in rows if r["kind"] == kind]
        at = np.array([r[key] for r in sel if r["human"]])
        off = np.array([r[key] for r in sel if not r["human"]])
        print(f"\n{kind}s: {len(at)} at human cuts, {len(off)} elsewhere")
        for name, v in (("at human cuts", at), ("elsewhere", off)):
            if len(v):
                q = np.percentile(v, [10, 25, 50, 75, 90])
                print(f"  {key} {name}: 10/25/50/75/90% = " + " / ".join(f"{x:.3g}" for x in q))
        print(f"  threshold  kept  at-human-cut  precision   (sigma >= 0.8 only: kept, at cut)")
        for t in thresholds:
            kept = [r for r in sel if keep(r[key], t)]
            good = [r for r in kept if r["human"]]
            smooth = [r for r in kept if r["sigma"] >= 0.8]
            smooth_good = [r for r in smooth if r["human"]]
            prec = len(good) / len(kept) if kept else float("nan")
            print(f"  {t:>9}  {len(kept):>4}  {len(good):>12}  {prec:>9.2f}   ({len(smooth)}, {len(smooth_good)})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
