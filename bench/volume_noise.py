#!/usr/bin/env python3
"""Parts of a noisy volume: pores, a hollow and surface noise (issue 12).

Writes a ball crossed by two rods (a body and four limbs: 5 parts) at 200^3,
then copies of it with voxels missing inside (cavities) or flipped near the
ball's surface (tunnels), segments each with every given skelseg binary
and prints, per case and binary, the part count, the largest object's
genus, the cavities and tunnel voxels filled, and the wall time.

With --generated, the shapes `skelseg generate` makes (at --generated-size)
instead, each clean and with 4% and 8% of the voxels within two voxels of
its surface flipped (a fixed hash of the position decides, as in the scene
test SceneVolumeNoise.SurfaceNoiseOfAFigureKeepsItsParts).

    /usr/bin/python3 bench/volume_noise.py --skelseg build/skelseg [--skelseg OTHER] [--size 200]
    /usr/bin/python3 bench/volume_noise.py --skelseg A --skelseg B --generated figure:0,y-arms,torus-limb

With --meshes, the voxel models of meshes instead (labels.nrrd > 0 of
`skelseg segment MESH --resolution` --generated-size, with the first binary),
each clean and with the same noise: real shapes as a scanner's volume would
hold them.

    /usr/bin/python3 bench/volume_noise.py --skelseg A --skelseg B --meshes ../shared/data/shapes/hand.off
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
    m = np.where(shell & (flip < 0.15), ~base, base)
    m |= flip > 0.995
    out.append(("15% flipped and 0.5% salt everywhere", m))
    return out


def read_nrrd(path):
    """The object voxels of a .nrrd skelseg wrote (uint8 masks of `generate`,
    little-endian uint16 labels of `segment`)."""
    import gzip
    data = open(path, "rb").read()
    end = data.index(b"\n\n")
    header = data[:end].decode()
    body = data[end + 2:]
    fields = dict(line.split(":", 1) for line in header.split("\n")[1:] if ":" in line)
    sizes = [int(v) for v in fields["sizes"].split()]
    if fields["encoding"].strip() == "gzip":
        body = gzip.decompress(body)
    dtype = {"uint8": np.uint8, "uint16": "<u2"}[fields["type"].strip()]
    return np.frombuffer(body, dtype=dtype).reshape(sizes[2], sizes[1], sizes[0]) > 0


def surface_noise(mask, rate256):
    from scipy import ndimage
    cube = np.ones((5, 5, 5), bool)
    near = ndimage.binary_dilation(mask, cube) & ~ndimage.binary_erosion(mask, cube, border_value=0)
    z, y, x = np.mgrid[:mask.shape[0], :mask.shape[1], :mask.shape[2]].astype(np.uint32)
    h = (x * np.uint32(73856093)) ^ (y * np.uint32(19349663)) ^ (z * np.uint32(83492791))
    h = (h * np.uint32(2654435761)) >> np.uint32(24)
    flip = near & (h < rate256)
    for axis in range(3):
        index = [slice(None)] * 3
        for edge in (slice(0, 2), slice(-2, None)):
            index[axis] = edge
            flip[tuple(index)] = False
    return np.where(flip, ~mask, mask)


def noise_levels(name, mask):
    """The clean mask and copies with 4% and 8% of its surface voxels flipped."""
    return [(f"{name} clean", mask), (f"{name}, 4% flipped", surface_noise(mask, 10)),
            (f"{name}, 8% flipped", surface_noise(mask, 20))]


def generated_cases(binary, names, size, work):
    out = []
    for name in names:
        shape, _, pose = name.partition(":")
        path = os.path.join(work, "generated.nrrd")
        command = [binary, "generate", shape, "-o", path, "--size", str(size)]
        if pose:
            command += ["--pose", pose]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        out += noise_levels(name, read_nrrd(path))
    return out


def mesh_cases(binary, meshes, size, work):
    out = []
    for mesh in meshes:
        model = os.path.join(work, "model")
        subprocess.run([binary, "segment", mesh, "-o", model, "--resolution", str(size), "-q",
                        "--no-preview", "--force"], check=True, stderr=subprocess.DEVNULL)
        out += noise_levels(os.path.basename(mesh), read_nrrd(os.path.join(model, "labels.nrrd")))
    return out


def write_nrrd(path, mask):
    n = mask.shape
    header = (f"NRRD0004\ntype: uint8\ndimension: 3\nsizes: {n[2]} {n[1]} {n[0]}\n"
              "encoding: raw\n\n")
    with open(path, "wb") as f:
        f.write(header.encode() + mask.astype(np.uint8).tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--skelseg", action="append",
                        help="a skelseg binary (repeat to compare; default build/skelseg)")
    parser.add_argument("--size", type=int, default=200)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--generated", default="", help="NAME[:POSE],... of skelseg generate")
    parser.add_argument("--generated-size", type=int, default=128,
                        help="grid of --generated shapes; resolution of --meshes")
    parser.add_argument("--meshes", default="", help="MESH,... voxelised, then made noisy")
    args = parser.parse_args()
    if not args.skelseg:
        repository = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        args.skelseg = [os.path.join(repository, "build", "skelseg")]
    with tempfile.TemporaryDirectory() as work:
        if args.meshes:
            all_cases = mesh_cases(args.skelseg[0], args.meshes.split(","), args.generated_size,
                                   work)
        elif args.generated:
            all_cases = generated_cases(args.skelseg[0], args.generated.split(","),
                                        args.generated_size, work)
        else:
            all_cases = cases(args.size)
        print("| case | " + " | ".join(f"`{b}`: parts, genus, cavities, tunnel voxels, s"
                                        for b in args.skelseg) + " |")
        print("| --- |" + " --- |" * len(args.skelseg))
        for name, mask in all_cases:
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
