#!/usr/bin/python3
"""Writes a PNG of one slice of a skelseg label volume (labels.nrrd).

Usage: tools/slice_png.py labels.nrrd OUT.png [--axis y] [--index middle]
Colours follow the preview palette order (tab20), background white. Used for
docs/gallery.md: the interior labels (each voxel takes the label of its
nearest boundary voxel) seen on a cut through the shape.
"""
import argparse, gzip, sys

import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, __file__.rsplit("/", 2)[0] + "/bench/peers")
from ft_vs_scipy import read_nrrd  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("labels")
    ap.add_argument("out")
    ap.add_argument("--axis", default="y", choices="xyz")
    ap.add_argument("--index", type=int, default=None)
    args = ap.parse_args()
    vol = read_nrrd(args.labels)  # z, y, x
    axis = {"z": 0, "y": 1, "x": 2}[args.axis]
    index = args.index if args.index is not None else vol.shape[axis] // 2
    sl = np.take(vol, index, axis=axis)
    cmap = plt.get_cmap("tab20")
    order = [0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 1, 3, 5, 7, 9, 11, 13, 15, 17, 19]
    rgb = np.ones(sl.shape + (3,))
    for label in np.unique(sl):
        if label:
            rgb[sl == label] = cmap(order[(int(label) - 1) % 20])[:3]
    fig = plt.figure(figsize=(sl.shape[1] / 40, sl.shape[0] / 40), dpi=80)
    plt.imshow(rgb, origin="lower", interpolation="nearest")
    plt.axis("off")
    plt.title(f"{args.labels.split('/')[-2]}: slice {args.axis} = {index}")
    fig.savefig(args.out, bbox_inches="tight")


if __name__ == "__main__":
    main()
