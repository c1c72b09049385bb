#!/usr/bin/python3
"""How many boundary voxels a unit of surface area gives, by shape and orientation.

tau, the skeleton's scale, is an area counted in boundary voxels (object
voxels with a background 6-neighbour, as kernels/BoundaryGraph counts them).
For a plane with unit normal n that count is max(|n_x|, |n_y|, |n_z|) per
unit of area: 1 where the surface faces an axis, 1/sqrt(3) where it faces a
diagonal. So the share of the boundary a limb carries, which tau is compared
with, depends on how the limb and the rest of the shape lie in the grid.
This script measures it on digital tubes (radius r, along an axis, at 30 and
45 degrees in a coordinate plane and along the space diagonal; the middle
half of a tube 12 r long, away from its ends) and digital spheres, and
prints boundary voxels per unit of true area:

    /usr/bin/python3 bench/digital_area.py
    /usr/bin/python3 bench/digital_area.py --radii 2,4,8 --json out.json

Needs numpy. The figures and what they mean for tau are in docs/quality.md
("Faithful surface areas: measured, not taken").
"""

import argparse
import json
import math
import sys

import numpy as np


def boundary_mask(inside):
    """Object voxels with at least one background 6-neighbour (outside the grid is background)."""
    padded = np.pad(inside, 1, constant_values=False)
    core = padded[1:-1, 1:-1, 1:-1]
    all_inside = core.copy()
    for axis in range(3):
        for shift in (-1, 1):
            all_inside &= np.roll(padded, shift, axis=axis)[1:-1, 1:-1, 1:-1]
    return core & ~all_inside


def tube_density(radius, direction):
    """Boundary voxels per unit of lateral area in the middle half of a digital tube."""
    d = np.asarray(direction, dtype=float)
    d /= np.linalg.norm(d)
    half_length = 6.0 * radius
    extent = int(math.ceil(half_length + radius)) + 2
    axis = np.arange(-extent, extent + 1, dtype=float) + 0.25  # off-centre: no symmetric ties
    x, y, z = np.meshgrid(axis, axis, axis, indexing="ij")
    along = x * d[0] + y * d[1] + z * d[2]
    radial_sq = x * x + y * y + z * z - along * along
    inside = (radial_sq <= radius * radius) & (np.abs(along) <= half_length)
    middle = np.abs(along) <= half_length / 2
    count = int((boundary_mask(inside) & middle).sum())
    return count / (2.0 * math.pi * radius * half_length)


def sphere_density(radius):
    extent = int(math.ceil(radius)) + 2
    axis = np.arange(-extent, extent + 1, dtype=float) + 0.25
    x, y, z = np.meshgrid(axis, axis, axis, indexing="ij")
    inside = x * x + y * y + z * z <= radius * radius
    return int(boundary_mask(inside).sum()) / (4.0 * math.pi * radius * radius)


def plane_density(normal):
    n = np.abs(np.asarray(normal, dtype=float))
    return float(n.max() / np.linalg.norm(n))


DIRECTIONS = {
    "axis": (0.0, 0.0, 1.0),
    "30 degrees": (math.sin(math.radians(30)), 0.0, math.cos(math.radians(30))),
    "45 degrees": (1.0, 0.0, 1.0),
    "diagonal": (1.0, 1.0, 1.0),
}


def main():
    parser = argparse.ArgumentParser(
        description="Boundary voxels per unit of true surface area on digital tubes and spheres."
    )
    parser.add_argument("--radii", default="2,3,4,6,8,12,16", help="comma-separated radii in voxels")
    parser.add_argument("--json", help="also write every number to this file")
    args = parser.parse_args()
    try:
        radii = [float(r) for r in args.radii.split(",") if r.strip()]
    except ValueError:
        parser.error(f"--radii: not a list of numbers: {args.radii!r}")
    if not radii or any(not (1.0 <= r <= 64.0) for r in radii):
        parser.error("--radii: give radii between 1 and 64 voxels")

    rows = []
    for r in radii:
        row = {"radius": r}
        for name, direction in DIRECTIONS.items():
            row[f"tube, {name}"] = tube_density(r, direction)
        row["sphere"] = sphere_density(r)
        rows.append(row)

    columns = [c for c in rows[0] if c != "radius"]
    print("Boundary voxels per unit of true area (a plane: 1 facing an axis, "
          f"{plane_density((1, 1, 1)):.3f} facing a diagonal)\n")
    print("| radius (voxels) | " + " | ".join(columns) + " |")
    print("| ---: | " + " | ".join("---:" for _ in columns) + " |")
    for row in rows:
        print(f"| {row['radius']:g} | " + " | ".join(f"{row[c]:.3f}" for c in columns) + " |")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as out:
            json.dump(rows, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
