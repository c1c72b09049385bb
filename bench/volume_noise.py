#!/usr/bin/env python3
"""Parts of a noisy volume: pores, a hollow and surface noise (issue 12).

Writes a ball crossed by two rods (a body and four limbs: 5 parts) at 200^3,
then copies of it with voxels missing inside (cavities) or flipped near the
ball's surface (tunnels), segments each with every given skelseg binary
and prints, per case and binary, the part count, the largest object's
genus, the cavities and tunnel voxels filled, and the wall time.

    /usr/bin/python3 bench/volume_noise.py --skelseg build/skelseg [--skelseg OTHER] [--size 200]
"""
import argparse
import json
import os
import subprocess
import tempfile
import time

import numpy as np


def figure(n):
    s = n / 200.0
    z, y, x = np.mgrid[:n, :n, :n].astype(np.float64)
    c = n / 2.0
    d = np.sqrt((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2)
    mask = d < 60 * s
    mask |= (np.sqrt((y - c) ** 2 + (z - c) ** 2) < 15 * s) & (x > 20 * s) & (x < 180 * s)
    mask |= (np.sqrt((x - c) ** 2 + (y - c) ** 2) < 12 * s) & (z > 20 * s) & (z < 190 * s)
    return mask, d, s, c, (x, y, z)


def cases(n):
    base, d, s, c, (x, y, z) = figure(n)
    shell = np.abs(d - 60 * s) < 3
    rng = np.random.default_rng(2)
    flip = rng.random(base.shape)
    out = [("clean", base)]
    one = base.copy()
    one[int(c), int(c), int(c + 50 * s)] = False
    out.append(("one voxel missing inside", one))
    for r in (3, 10, 25):
        hollow = base & ~(np.sqrt((x - c - 30 * s) ** 2 + (y - c) ** 2 + (z - c) ** 2) < r)
        out.append((f"hollow ball of radius {r}", hollow))
    for pin in (0.01, 0.03):
        m = base.copy()
        m[shell & base & (flip < pin)] = False
        out.append((f"{pin:.0%} removed within 3 of the surface", m))
    for pout in (0.01, 0.03, 0.08):
        m = base.copy()
        m[shell & ~base & (flip < pout)] = True
        out.append((f"{pout:.0%} added within 3 of the surface", m))
    for p in (0.02, 0.03, 0.05):
        m = base.copy()
        m[shell & ~base & (flip < p)] = True
        m[shell & base & (flip < p)] = False
        out.append((f"{p:.0%} added and {p:.0%} removed", m))
    return out


def write_nrrd(path, mask):
    n = mask.shape
    header = (f"NRRD0004\ntype: uint8\ndimension: 3\nsizes: {n[2]} {n[1]} {n[0]}\n"
              "encoding: raw\n\n")
    with open(path, "wb") as f:
        f.write(header.encode() + mask.astype(np.uint8).tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--skelseg", action="append", required=True)
    parser.add_argument("--size", type=int, default=200)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        print("| case | " + " | ".join(f"`{b}`: parts, genus, cavities, tunnel voxels, s"
                                        for b in args.skelseg) + " |")
        print("| --- |" + " --- |" * len(args.skelseg))
        for name, mask in cases(args.size):
            path = os.path.join(work, "in.nrrd")
            write_nrrd(path, mask)
            cells = []
            for b in args.skelseg:
                out = os.path.join(work, "out")
                start = time.monotonic()
                subprocess.run([b, "segment", path, "-o", out, "-q", "--no-preview", "--force",
                                "--threads", str(args.threads)], check=True)
                seconds = time.monotonic() - start
                with open(os.path.join(out, "report.json")) as f:
                    report = json.load(f)
                o = max(report["objects"], key=lambda o: o["voxels"])
                cells.append(f"{report['segment_count']}, {o['genus']}, {o.get('cavities', '-')}, "
                             f"{o.get('tunnel_voxels', '-')}, {seconds:.1f}")
            print(f"| {name} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
