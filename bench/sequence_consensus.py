#!/usr/bin/python3
"""One segmentation per pose sequence: `skelseg sequence` on every sequence.

For every pose sequence DATA/poses/NAME_FRAME.obj (frames grouped and ordered
as bench/invariance.py does) runs

    skelseg sequence FRAME... -o OUT/NAME --resolution R -q --no-preview

and tabulates, from OUT/NAME/sequence.json: the parts of each frame's own
segmentation (marked where the frame did not vote: its voxel model has
handles its mesh lacks), the frame chosen and its part count (every frame takes its
labels, so the frames of the output have one part count and no error between
them, by construction), the mean Rand Index error between the frames' own
segmentations, and the mean error of the frames' own segmentations to the
consensus (how much the consensus overrides the single frames).

    /usr/bin/python3 bench/sequence_consensus.py
    /usr/bin/python3 bench/sequence_consensus.py --data DATA --sequences lion,cat --json out.json

Where DATA/poses is absent it says so and exits 0.
"""

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from invariance import binary_and_data_parser, pose_sequences  # noqa: E402  (one grouping)


def parse_args(argv):
    p = binary_and_data_parser(__doc__)
    p.add_argument("--resolution", type=int, default=192, help="resolution (default 192)")
    p.add_argument("--sequences", default="",
                   help="comma-separated sequence names (default: every one)")
    p.add_argument("--workdir", default=None,
                   help="keep the outputs here (default: a temporary folder)")
    p.add_argument("--json", default=None, help="write every number to this JSON file")
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    poses = Path(args.data) / "poses"
    if not poses.is_dir():
        print(f"sequence_consensus: {poses} is absent; nothing to measure")
        return 0
    sequences = pose_sequences(poses)
    if args.sequences:
        wanted = args.sequences.split(",")
        unknown = [name for name in wanted if name not in sequences]
        if unknown:
            print(f"sequence_consensus: no sequence {', '.join(unknown)} in {poses}",
                  file=sys.stderr)
            return 2
        sequences = {name: sequences[name] for name in wanted}
    with tempfile.TemporaryDirectory() as temporary:
        root = Path(args.workdir or temporary)
        rows = []
        for name, frames in sequences.items():
            out = root / name
            start = time.monotonic()
            run = subprocess.run([args.skelseg, "sequence", *map(str, frames), "-o", str(out),
                                  "--resolution", str(args.resolution), "-q", "--no-preview",
                                  "--force"], capture_output=True, text=True)
            if run.returncode != 0:
                print(f"sequence_consensus: {name}: exit {run.returncode}: {run.stderr.strip()}",
                      file=sys.stderr)
                return 1
            summary = json.loads((out / "sequence.json").read_text())
            frame_rows = summary["frames"]
            rows.append({
                "sequence": name,
                "frames": [Path(f["input"]).stem.rpartition("_")[2] for f in frame_rows],
                "parts": [f["parts"] for f in frame_rows],
                # Frames whose voxel model has handles their mesh lacks do
                # not vote (docs/outputs.md); older binaries do not say.
                "voted": [f.get("voted", True) for f in frame_rows],
                "chosen": summary["reference_frame"],
                "consensus_parts": summary["modal_parts"],
                "mean_error_between_frames": summary["mean_rand_index_error"],
                "mean_error_to_consensus": sum(f["rand_index_error_to_consensus"]
                                               for f in frame_rows) / len(frame_rows),
                "seconds": time.monotonic() - start,
            })
    print(f"Pose sequences, `skelseg sequence` at resolution {args.resolution}:\n")
    print("| sequence | frames | parts of each frame's own segmentation (* did not vote) | "
          "frame chosen | "
          "consensus parts (every frame) | mean RI error between the frames' own | "
          "mean RI error of the frames' own to the consensus | wall s |")
    print("| --- | --- | --- | --- | ---: | ---: | ---: | ---: |")
    for r in rows:
        print(f"| {r['sequence']} | {', '.join(r['frames'])} | "
              f"{', '.join(f'{p}' + ('' if v else '*') for p, v in zip(r['parts'], r['voted']))} | "
              f"{r['frames'][r['chosen']]} | "
              f"{r['consensus_parts']} | {r['mean_error_between_frames']:.3f} | "
              f"{r['mean_error_to_consensus']:.3f} | {r['seconds']:.1f} |")
    if rows:
        steady = sum(len(set(r["parts"])) == 1 for r in rows)
        print(f"\nOwn segmentations with one part count in every frame: {steady} of {len(rows)}; "
              f"with `skelseg sequence`: {len(rows)} of {len(rows)} (by construction). Mean error "
              f"between frames {sum(r['mean_error_between_frames'] for r in rows) / len(rows):.3f} "
              f"-> 0; mean error of the frames' own to the consensus "
              f"{sum(r['mean_error_to_consensus'] for r in rows) / len(rows):.3f}.")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
