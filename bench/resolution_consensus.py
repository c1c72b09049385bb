#!/usr/bin/python3
"""How much of the parts' change between poses is the voxel grid's (issue 12).

Each frame DATA/poses/NAME_FRAME.obj is segmented at several resolutions
around --resolution (skelseg segment MESH -o OUT --resolution R, defaults
otherwise), and each frame's labels are replaced by the consensus of its
runs: skelseg.sequence_consensus, the rule of `skelseg sequence` (the part
count most runs give, then the run closest to the others), applied to the
runs of one mesh, whose faces are the same. The table compares the pose
sequences as bench/invariance.py does (parts per frame, mean Rand Index
error between frames) for the single resolution and for each set of
resolutions. Were the changes between poses the grid's noise (a measure
falling on either side of a threshold by where the voxels lie), the
consensus of nearby resolutions would remove them; what it leaves is the
poses' own doing. The result is docs/quality.md, "Several resolutions per
frame: measured, not taken".

    /usr/bin/python3 bench/resolution_consensus.py --data DATA --workdir W \\
        --resolutions 144,160,176,192,208,224,240 --sets 192 176,192,208 160,176,192,208,224

Runs are kept in W/NAME_FRAME/R (reused when present). Needs numpy and the
skelseg module (PYTHONPATH=build/python).
"""

import argparse
import concurrent.futures
import itertools
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from invariance import pose_sequences, rand_index_error, read_labels, segment  # noqa: E402

REPO = Path(__file__).resolve().parent.parent


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"))
    p.add_argument("--data", required=True, help="a folder holding poses/NAME_FRAME.obj")
    p.add_argument("--workdir", required=True)
    p.add_argument("--resolutions", default="144,160,176,192,208,224,240")
    p.add_argument("--sets", nargs="+", default=["192", "176,192,208", "160,176,192,208,224",
                                                 "144,160,176,192,208,224,240"],
                   help="resolution sets whose consensus is compared (one value: that run)")
    p.add_argument("--jobs", type=int, default=2)
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    import skelseg  # the engine's consensus rule, not a copy of it

    sequences = pose_sequences(Path(args.data) / "poses")
    if not sequences:
        print(f"{args.data}/poses holds no pose sequence")
        return 0
    resolutions = sorted({int(r) for s in args.sets for r in s.split(",")} |
                         {int(r) for r in args.resolutions.split(",")})
    work = Path(args.workdir)
    runs = [(mesh, r) for frames in sequences.values() for mesh in frames for r in resolutions]

    def run(item):
        mesh, resolution = item
        out = work / mesh.stem / str(resolution)
        if not (out / "segmentation.seg").exists():
            segment(args.skelseg, mesh, out, resolution)
        return item, read_labels(out / "segmentation.seg")

    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        labels = dict(pool.map(run, runs))

    print("| resolutions per frame | same part count in every frame | mean RI error between frames |"
          " parts per frame |")
    print("| --- | --- | ---: | --- |")
    for choice in args.sets:
        chosen = [int(r) for r in choice.split(",")]
        kept, errors, detail = 0, [], []
        for name, frames in sequences.items():
            frame_labels = []
            for mesh in frames:
                own = [labels[(mesh, r)] for r in chosen]
                pick = 0 if len(own) == 1 else skelseg.sequence_consensus(own).reference
                frame_labels.append(own[pick])
            parts = [int(np.unique(f).size) for f in frame_labels]
            kept += len(set(parts)) == 1
            errors.append(float(np.mean([rand_index_error(a, b)
                                         for a, b in itertools.combinations(frame_labels, 2)])))
            detail.append(f"{name} {', '.join(map(str, parts))}")
        print(f"| {choice} | {kept} of {len(sequences)} | {np.mean(errors):.3f} | "
              f"{'; '.join(detail)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
