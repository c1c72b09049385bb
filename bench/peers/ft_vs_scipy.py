#!/usr/bin/python3
"""Feature transform: skelseg against scipy, on the same volume, in one run.

Usage: bench/peers/ft_vs_scipy.py MESH_OR_VOLUME [--resolution N] [--skelseg build/skelseg] [--repeat 3]

1. skelseg segments the input once (mesh: voxelised at N) to get the object
   mask (labels.nrrd, nonzero = object).
2. scipy.ndimage.distance_transform_edt(..., return_indices=True) computes the
   nearest boundary voxel of every voxel of that grid (the same problem the
   feature transform stage solves: sites = 6-boundary voxels).
3. skelseg segments the mask volume itself --repeat times with --threads 1;
   its 'feature transform' stage time (boundary extraction + exact feature
   transform) comes from report.json.
Prints medians and the speed-up. Run with Debian's /usr/bin/python3 (numpy, scipy).
"""
import argparse, gzip, json, os, statistics, subprocess, sys, tempfile, time

import numpy as np
from scipy import ndimage


def read_nrrd(path):
    with open(path, "rb") as f:
        data = f.read()
    header, _, payload = data.partition(b"\n\n")
    fields = {}
    for line in header.decode().splitlines()[1:]:
        if ":" in line and not line.startswith("#"):
            k, _, v = line.partition(":")
            fields[k.strip()] = v.strip().lstrip("=").strip()
    sizes = [int(s) for s in fields["sizes"].split()]
    dtype = {"uint16": "<u2", "unsigned short": "<u2", "ushort": "<u2", "uint8": "u1", "uchar": "u1",
             "unsigned char": "u1"}[fields["type"]]
    if fields.get("encoding") in ("gzip", "gz"):
        payload = gzip.decompress(payload)
    return np.frombuffer(payload, dtype=dtype).reshape(sizes[::-1])  # z, y, x


def write_nrrd_mask(path, mask):
    z, y, x = mask.shape
    header = f"NRRD0004\ntype: uint8\ndimension: 3\nsizes: {x} {y} {z}\nencoding: raw\n\n"
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(np.ascontiguousarray(mask, dtype=np.uint8).tobytes())


def skelseg_ft_seconds(skelseg, volume, outdir, threads):
    subprocess.run([skelseg, "segment", volume, "-o", outdir, "--force", "-q", "--no-preview",
                    "--threads", str(threads)], check=True)
    with open(os.path.join(outdir, "report.json")) as f:
        report = json.load(f)
    return sum(s["wall_seconds"] for s in report["stages"] if s["name"] == "feature transform")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("input")
    ap.add_argument("--resolution", type=int, default=400)
    ap.add_argument("--skelseg", default="build/skelseg")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="skelseg-ft-")
    subprocess.run([args.skelseg, "segment", args.input, "-o", os.path.join(work, "first"), "-q", "--no-preview",
                    "--resolution", str(args.resolution)], check=True)
    mask = read_nrrd(os.path.join(work, "first", "labels.nrrd")) > 0
    volume = os.path.join(work, "mask.nrrd")
    write_nrrd_mask(volume, mask)
    # 6-boundary: object voxels with a face neighbour outside (grid border counts as outside).
    padded = np.pad(mask, 1)
    inner = padded[1:-1, 1:-1, 1:-1]
    interior = inner.copy()
    for axis in range(3):
        for shift in (-1, 1):
            interior &= np.roll(padded, shift, axis=axis)[1:-1, 1:-1, 1:-1]
    boundary = inner & ~interior
    scipy_times, ours1, ours = [], [], []
    for _ in range(args.repeat):
        t = time.perf_counter()
        ndimage.distance_transform_edt(~boundary, return_indices=True)
        scipy_times.append(time.perf_counter() - t)
        ours1.append(skelseg_ft_seconds(args.skelseg, volume, os.path.join(work, "t1"), 1))
        ours.append(skelseg_ft_seconds(args.skelseg, volume, os.path.join(work, "tn"), os.cpu_count() or 1))
    s, o1, on = statistics.median(scipy_times), statistics.median(ours1), statistics.median(ours)
    result = {"input": args.input, "resolution": args.resolution, "grid": list(mask.shape[::-1]),
              "object_voxels": int(mask.sum()), "boundary_voxels": int(boundary.sum()),
              "scipy_edt_indices_seconds": s, "skelseg_ft_seconds_1_thread": o1,
              "skelseg_ft_seconds_all_threads": on, "speedup_1_thread": s / o1 if o1 else None,
              "repeats": args.repeat}
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    sys.exit(main())
