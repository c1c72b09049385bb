#!/usr/bin/python3
"""Lay out pose sequences the shared data lacks, for bench/invariance.py.

Issue 12 asks that parts stay the same across the poses of characters
nobody tuned on. The shared poses (../shared/data/poses) come from the
public repository CraGL/Hyperspectral-Inverse-Skinning, whose models/ folder
holds many more frames and characters. Give this script a copy of that
repository (a clone with a work tree, or a bare clone: files are then read
with `git show`) and it writes four sets of frames, each in the layout
bench/invariance.py and bench/sequence_consensus.py read (`--data OUT/SET`):

    OUT/traced/poses/NAME_FRAME.obj    12 sequences, 4 frames each: the
                                       frames every rule since the sixth
                                       session was traced on
    OUT/untraced/poses/NAME_FRAME.obj  13 sequences of other frames of the
                                       same characters (first read in the
                                       tenth session)
    OUT/third/poses/NAME_FRAME.obj     7 sequences read first on 2026-12-06:
                                       other frames of the shared characters
                                       (elephant-gallop, samba, pdance) and
                                       of four others (horse-collapse, a
                                       horse squashed flat, is no pose
                                       sequence and is left out)
    OUT/fourth/poses/NAME_FRAME.obj    4 sequences read first on 2026-12-07:
                                       the models no set held before (a
                                       twisted cube, two bent open tubes, a
                                       face's expressions)

The tables of docs/quality.md name the set they were measured on. Files
are copied byte for byte; nothing is written into the repository, and the
copy of CraGL's repository is only read. A frame whose bytes equal a shared
frame's is left out with a line saying so (the shared data is not held
out), as is a frame missing from the copy. Exit 2 when the copy has no
models/ folder. Only the standard library (and git, for a bare clone) is
needed.

    git clone https://github.com/CraGL/Hyperspectral-Inverse-Skinning ~/hyperspectral
    /usr/bin/python3 bench/heldout_poses.py --repo ~/hyperspectral --out ~/poses-heldout
    /usr/bin/python3 bench/invariance.py --data ~/poses-heldout/third --shapes '' --jobs 2
"""

import argparse
import hashlib
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


# Where each sequence's frames lie under models/: folder and file name.
SEQUENCES = {
    "cat": ("cat-poses", "{:04d}.obj"),
    "chebu3": ("cheburashka-all/poses-3", "cheburashka-{}.obj"),
    "cheburashka": ("cheburashka", "cheburashka-{}.obj"),
    "chicken": ("chickenCrossing", "{}.obj"),
    "cow": ("cow", "cow-{}.obj"),
    "cube": ("cube", "cube-{}.obj"),
    "cylinder": ("cylinder", "cylinder-{}.obj"),
    "cylp2": ("cylinder-all/poses-2", "cylinder-{}.obj"),
    "face": ("face-poses", "{}.obj"),
    "crane": ("crane", "mesh_{:04d}.obj"),
    "elephantgallop": ("elephant-gallop", "{}.obj"),
    "elephantposes": ("elephant-poses", "{}.obj"),
    "horsegallop": ("horse-gallop", "{:04d}.obj"),
    "horseposes": ("horse-poses", "{}.obj"),
    "lion": ("lion-poses", "{}.obj"),
    "pcow": ("pcow", "{}.obj"),
    "pdance": ("pdance", "{}.obj"),
    "pjump": ("pjump", "{}.obj"),
    "samba": ("samba", "mesh_{:04d}.obj"),
    "wolf": ("wolf-all/poses-2", "wolf-{}.obj"),
    "wolfp1": ("wolf-all/poses-1", "wolf-{}.obj"),
}

# The frames of each sequence in each set.
FRAMES = {
    "traced": {
        "cat": [1, 4, 7, 9], "cheburashka": ["01", "04", "07", "10"],
        "chicken": [1, 100, 200, 300], "cow": [1, 3, 5, 7], "crane": [0, 50, 100, 150],
        "elephantposes": [1, 4, 7, 9], "horsegallop": [1, 13, 25, 37],
        "horseposes": [1, 4, 7, 9], "lion": [1, 4, 7, 9], "pcow": [1, 50, 100, 150],
        "pjump": [1, 50, 100, 150], "wolf": [1, 5, 10, 15],
    },
    "untraced": {
        "cat": [2, 3, 5, 6], "chebu3": [1, 2, 3, 4], "cheburashka": ["02", "05", "08", "11"],
        "chicken": [51, 151, 251, 351], "cow": [2, 4, 6], "crane": [25, 75, 125],
        "elephantposes": [2, 3, 5, 10], "horsegallop": [7, 19, 31, 43],
        "horseposes": [2, 3, 5, 10], "lion": [2, 3, 5, 6], "pcow": [26, 76, 126, 201],
        "pjump": [26, 76, 126, 201], "wolfp1": [1, 2, 3, 4],
    },
    "third": {
        "elephantgallop": [7, 19, 31, 43], "samba": [20, 60, 100, 140],
        "pdance": [25, 75, 125, 175], "chicken": [26, 126, 226, 326],
        "pcow": [10, 60, 110, 160], "pjump": [10, 60, 110, 160], "crane": [10, 60, 110, 160],
    },
    "fourth": {
        "cube": [1, 2, 3, 4], "cylinder": [1, 2, 3, 4],
        "cylp2": [1, 2, 3, 4], "face": [1, 4, 7, 9],
    },
}

# (sequence name, frame, path under models/) for every frame of each set.
def _paths(sequences):
    paths = []
    for sequence, frames in sequences.items():
        folder, name = SEQUENCES[sequence]
        paths += [(sequence, str(frame), f"{folder}/{name.format(frame)}") for frame in frames]
    return paths


SETS = {name: _paths(sequences) for name, sequences in FRAMES.items()}


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repo", required=True,
                   help="a copy of CraGL/Hyperspectral-Inverse-Skinning (work tree or bare clone)")
    p.add_argument("--out", required=True, help="folder to write the sets into")
    p.add_argument("--sets", default=",".join(SETS),
                   help="comma-separated sets to write (default: " + ",".join(SETS) + ")")
    p.add_argument("--shared", default=str(REPO.parent / "shared" / "data"),
                   help="the shared data folder, whose poses are never written "
                        "(default: ../shared/data next to the repository)")
    return p.parse_args(argv)


class Source:
    """Reads models/... from a work tree, or from a bare clone with git show."""

    def __init__(self, repo):
        self.repo = Path(repo)
        self.tree = (self.repo / "models").is_dir()
        self.bare = not self.tree and subprocess.run(
            ["git", "--git-dir", str(self.repo), "rev-parse", "--verify", "-q", "HEAD:models"],
            capture_output=True).returncode == 0

    def usable(self):
        return self.tree or self.bare

    def read(self, path):
        """The bytes of models/PATH, or None when the copy lacks it."""
        if self.tree:
            file = self.repo / "models" / path
            return file.read_bytes() if file.is_file() else None
        shown = subprocess.run(["git", "--git-dir", str(self.repo), "show", f"HEAD:models/{path}"],
                               capture_output=True)
        return shown.stdout if shown.returncode == 0 else None


def shared_digests(shared):
    folder = Path(shared) / "poses"
    if not folder.is_dir():
        return set()
    return {hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.glob("*.obj")}


def lay_out(source, out, sets, shared, log=print):
    """Writes the frames of `sets`; returns {set: [file names written]}."""
    out = Path(out).resolve()
    if out == REPO or REPO in out.parents:
        raise ValueError(f"{out} is inside the repository; write the held-out frames elsewhere")
    for name in sets:
        if name not in SETS:
            raise ValueError(f"no set '{name}' (sets: {', '.join(SETS)})")
    held = shared_digests(shared)
    written = {}
    for name in sets:
        folder = out / name / "poses"
        folder.mkdir(parents=True, exist_ok=True)
        written[name] = []
        for sequence, frame, path in SETS[name]:
            data = source.read(path)
            if data is None:
                log(f"heldout_poses.py: {name}: models/{path} is not in the copy; left out")
                continue
            if hashlib.sha256(data).hexdigest() in held:
                log(f"heldout_poses.py: {name}: models/{path} is a shared frame; left out")
                continue
            target = folder / f"{sequence}_{frame}.obj"
            target.write_bytes(data)
            written[name].append(target.name)
    return written


def main(argv):
    args = parse_args(argv)
    source = Source(args.repo)
    if not source.usable():
        print(f"heldout_poses.py: {args.repo}: no models/ folder (a copy of "
              "CraGL/Hyperspectral-Inverse-Skinning is needed)", file=sys.stderr)
        return 2
    try:
        written = lay_out(source, args.out, [s for s in args.sets.split(",") if s],
                          args.shared, log=lambda line: print(line, file=sys.stderr))
    except ValueError as error:
        print(f"heldout_poses.py: {error}", file=sys.stderr)
        return 2
    for name, files in written.items():
        sequences = sorted({f.rsplit("_", 1)[0] for f in files})
        print(f"{name}: {len(files)} frames of {len(sequences)} sequences in "
              f"{Path(args.out) / name / 'poses'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
