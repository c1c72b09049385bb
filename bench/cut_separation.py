#!/usr/bin/python3
"""Counts the cut loops that separate nothing in skelseg outputs.

For every output folder (labels.nrrd and cuts.ply of one `skelseg segment`
run), each loop of cuts.ply is compared with the labels around it: the object
voxels within --radius voxels of the loop, split by the loop's plane (the
plane through the loop's centre across its smallest principal axis; voxels
within one voxel of the plane are left out). A loop whose two sides carry the
same majority label "leaves the same label on both sides": either it
separates nothing, or the piece it cuts off merged into its neighbour (§9.2
of docs/algorithm.md); report.json's `cuts` entries (`separates`, where the
binary writes it) tell the two apart.

Usage: bench/cut_separation.py OUT_DIR [OUT_DIR ...] [--radius 3] [--list]
Prints one line per folder with loops that leave one label, and the totals.
"""
import argparse
import gzip
import json
import struct
import sys
from pathlib import Path

import numpy as np


def read_nrrd(path):
    """labels.nrrd: the volume (z, y, x), the origin and the voxel spacing."""
    data = Path(path).read_bytes()
    header, _, payload = data.partition(b"\n\n")
    fields = {}
    for line in header.decode().splitlines()[1:]:
        if ":" in line and not line.startswith("#"):
            key, _, value = line.partition(":")
            fields[key.strip()] = value.strip()
    sizes = [int(s) for s in fields["sizes"].split()]
    dtype = {"uint16": "<u2", "uint8": "u1"}[fields["type"]]
    if fields.get("encoding") in ("gzip", "gz"):
        payload = gzip.decompress(payload)
    volume = np.frombuffer(payload, dtype=dtype).reshape(sizes[::-1])
    origin = np.array([float(v) for v in fields["space origin"].strip("()").split(",")])
    directions = [d.strip("()").split(",") for d in fields["space directions"].split()]
    spacing = np.array([float(directions[i][i]) for i in range(3)])
    return volume, origin, spacing


def read_cut_loops(path):
    """cuts.ply (binary little endian): the loops' vertices, one array per loop."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    vertices = int(header.split("element vertex ")[1].split()[0])
    rows = struct.unpack_from("<" + "fffi" * vertices, data, end)
    loops = {}
    for i in range(vertices):
        x, y, z, cut = rows[4 * i:4 * i + 4]
        loops.setdefault(cut, []).append((x, y, z))
    return [np.array(loops[k]) for k in sorted(loops)]


def loop_sides(volume, grid_points, radius):
    """Majority label on each side of one loop (0 where a side has no object voxel)."""
    centre = grid_points.mean(axis=0)
    _, _, axes = np.linalg.svd(grid_points - centre)
    normal = axes[2]
    lo = np.maximum(np.floor(grid_points.min(axis=0) - radius).astype(int), 0)
    hi = np.minimum(np.ceil(grid_points.max(axis=0) + radius).astype(int) + 1,
                    np.array(volume.shape[::-1]))
    box = volume[lo[2]:hi[2], lo[1]:hi[1], lo[0]:hi[0]]
    z, y, x = np.nonzero(box)
    if x.size == 0:
        return 0, 0
    voxels = np.stack([x + lo[0], y + lo[1], z + lo[2]], axis=1).astype(float)
    labels = box[z, y, x]
    near = np.zeros(len(voxels), dtype=bool)
    for start in range(0, len(grid_points), 64):
        chunk = grid_points[start:start + 64]
        d2 = ((voxels[:, None, :] - chunk[None, :, :]) ** 2).sum(axis=2).min(axis=1)
        near |= d2 <= radius * radius
    offset = (voxels - centre) @ normal
    sides = []
    for keep in (near & (offset >= 1.0), near & (offset <= -1.0)):
        values = labels[keep]
        sides.append(int(np.bincount(values).argmax()) if values.size else 0)
    return sides[0], sides[1]


def check(folder, radius):
    volume, origin, spacing = read_nrrd(folder / "labels.nrrd")
    loops = read_cut_loops(folder / "cuts.ply") if (folder / "cuts.ply").exists() else []
    report = {}
    if (folder / "report.json").exists():
        report = json.loads((folder / "report.json").read_text())
    flags = [c.get("separates") for c in report.get("cuts", [])]
    same = []
    for index, loop in enumerate(loops):
        a, b = loop_sides(volume, (loop - origin) / spacing, radius)
        if a == b:
            same.append((index, a, flags[index] if index < len(flags) else None))
    return len(loops), same


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("folders", nargs="+", help="skelseg output folders")
    p.add_argument("--radius", type=float, default=3.0,
                   help="voxels around the loop that count (default 3)")
    p.add_argument("--list", action="store_true", help="print every folder, not only those hit")
    args = p.parse_args(argv)
    total_loops = total_same = 0
    for name in args.folders:
        folder = Path(name)
        if not (folder / "labels.nrrd").exists():
            print(f"{folder}: no labels.nrrd, skipped", file=sys.stderr)
            continue
        loops, same = check(folder, args.radius)
        total_loops += loops
        total_same += len(same)
        if same or args.list:
            detail = ", ".join(f"loop {i} (label {label}"
                               + ("" if flag is None else f", separates {str(flag).lower()}") + ")"
                               for i, label, flag in same)
            print(f"{folder}: {loops} loops, {len(same)} leave one label" +
                  (f": {detail}" if detail else ""))
    print(f"total: {total_loops} loops in {len(args.folders)} folders, "
          f"{total_same} leave the same label on both sides")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
