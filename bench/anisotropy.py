#!/usr/bin/python3
"""Volumes of anisotropic voxels: cubic voxels against the file's own.

Each mesh of DATA/shapes is voxelised at --resolution (`skelseg segment MESH
--resolution R`); its labels.nrrd, made binary, is the cubic original. From
it, copies keep every k-th slice along one axis (k = 2 or 3 along z, 2
along x) with that axis's spacing k, as a scan with thicker slices would
give. Each copy is segmented twice,

    skelseg segment COPY -o OUT -q --no-preview --force --threads 2
    skelseg segment COPY -o OUT -q --no-preview --force --threads 2 --keep-voxel-aspect

(cubic voxels, the default, and the file's own voxels), and compared with
the cubic original's segmentation at the copy's voxel centres: parts, and
the Rand Index error over the object voxels of either (1 - RI, as
bench/invariance.py counts it). The table goes into docs/formats.md,
"Anisotropic voxels".

    /usr/bin/python3 bench/anisotropy.py --workdir /tmp/anisotropy

Where DATA is absent it says so and exits 0. Needs numpy.
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cut_separation import read_nrrd  # noqa: E402  (one NRRD reader for the benchmarks)
from invariance import binary_and_data_parser, rand_index_error  # noqa: E402

COPIES = [(2, 2), (2, 3), (0, 2)]  # (axis, every k-th slice)


def parse_args(argv):
    p = binary_and_data_parser(__doc__)
    p.add_argument("--shapes", default="",
                   help="comma-separated files of DATA/shapes (default: every one)")
    p.add_argument("--resolution", type=int, default=192, help="voxelisation (default 192)")
    p.add_argument("--workdir", default=None,
                   help="keep the volumes and segmentations here (default: a temporary folder)")
    return p.parse_args(argv)


def write_mask(path, mask, spacing):
    """mask indexed (x, y, z) as a raw NRRD with `spacing`."""
    header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: {} {} {}\n" \
             "spacings: {} {} {}\nencoding: raw\n\n".format(*mask.shape, *spacing)
    path.write_bytes(header.encode() + mask.astype(np.uint8).tobytes(order="F"))


def segment(skelseg, source, out, *extra):
    subprocess.run([skelseg, "segment", str(source), "-o", str(out), "-q", "--no-preview",
                    "--force", "--threads", "2", *extra], check=True)
    labels = read_nrrd(out / "labels.nrrd")[0].transpose(2, 1, 0)  # (x, y, z)
    return len(np.unique(labels[labels > 0])), labels


def main(argv):
    args = parse_args(argv)
    shapes_dir = Path(args.data) / "shapes"
    if not shapes_dir.is_dir():
        print(f"no shapes in {shapes_dir}: nothing to measure")
        return 0
    names = args.shapes.split(",") if args.shapes else sorted(p.name for p in shapes_dir.iterdir())
    work = Path(args.workdir or tempfile.mkdtemp(prefix="skelseg-anisotropy-"))
    work.mkdir(parents=True, exist_ok=True)
    print("| shape | copy | parts: cubic original / cubic voxels / own voxels | "
          "RI error: cubic voxels / own voxels |")
    print("| --- | --- | --- | --- |")
    rows = []
    for name in names:
        stem = Path(name).stem
        mesh_out = work / f"{stem}-mesh"
        subprocess.run([args.skelseg, "segment", str(shapes_dir / name), "-o", str(mesh_out),
                        "-q", "--no-preview", "--force", "--resolution", str(args.resolution)],
                       check=True)
        mask = read_nrrd(mesh_out / "labels.nrrd")[0].transpose(2, 1, 0) > 0
        original = work / f"{stem}.nrrd"
        write_mask(original, mask, (1, 1, 1))
        parts, labels = segment(args.skelseg, original, work / f"{stem}-cubic")
        for axis, k in COPIES:
            keep = [slice(None)] * 3
            keep[axis] = slice(k // 2, None, k)
            copy = mask[tuple(keep)]
            spacing = [1, 1, 1]
            spacing[axis] = k
            path = work / f"{stem}-{'xyz'[axis]}{k}.nrrd"
            write_mask(path, copy, spacing)
            # The original's labels at the copy's voxel centres.
            index = np.indices(copy.shape)
            index[axis] = index[axis] * k + k // 2
            reference = labels[index[0], index[1], index[2]]
            cubic_parts, cubic = segment(args.skelseg, path, work / f"{path.stem}-cubic")
            own_parts, own = segment(args.skelseg, path, work / f"{path.stem}-own",
                                     "--keep-voxel-aspect")
            voxels = (reference > 0) | (cubic > 0) | (own > 0)
            rows.append((parts, cubic_parts, own_parts,
                         rand_index_error(cubic[voxels], reference[voxels]),
                         rand_index_error(own[voxels], reference[voxels])))
            print(f"| {stem} | {'xyz'[axis]} x{k} | {parts} / {cubic_parts} / {own_parts} | "
                  f"{rows[-1][3]:.3f} / {rows[-1][4]:.3f} |", flush=True)
    if rows:
        same = [sum(r[i] == r[0] for r in rows) for i in (1, 2)]
        print(f"\nSame part count as the cubic original: cubic voxels {same[0]} of {len(rows)}, "
              f"own voxels {same[1]} of {len(rows)}; mean RI error: cubic voxels "
              f"{np.mean([r[3] for r in rows]):.3f}, own voxels {np.mean([r[4] for r in rows]):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
