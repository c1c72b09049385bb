#!/usr/bin/python3
"""Lay out the Princeton benchmark models that the shared subset lacks, for the bench scripts.

The shared data (../shared/data/psb) holds 45 of the benchmark's 380 models,
and every rule of the engine was traced on them. To check a change on models
nobody tuned on, give this script a copy of the whole benchmark, as
Princeton distributes it (MeshsegBenchmark-1.0: data/off/N.off and
data/seg/Benchmark/N/N_k.seg), and it writes, for every model that is not in
the shared subset,

    OUT/psb/off/N.off               the mesh, copied
    OUT/psb/seg/N/N_k.seg.gz        its human segmentations, gzipped
    OUT/psb/CATEGORIES.tsv          N<TAB>category (the benchmark's numbering:
                                    twenty models per category)

which is the layout bench/psb_benchmark.py, bench/invariance.py --psb and
bench/time_budget.py read (`--data OUT`). Nothing is written into the
repository, and the benchmark copy is only read.

    /usr/bin/python3 bench/heldout_psb.py --benchmark ~/MeshsegBenchmark-1.0 --out ~/psb-heldout
    /usr/bin/python3 bench/psb_benchmark.py --data ~/psb-heldout --categories articulated

A model is left out, with a line saying why, when its mesh is not a readable
OFF file or a human segmentation does not have one label per face. Exit 2
when the benchmark folder has no data/off. Only the standard library is
needed.
"""

import argparse
import gzip
import shutil
import sys
from pathlib import Path

from psb_benchmark import read_labels

REPO = Path(__file__).resolve().parent.parent

# The benchmark's categories, twenty models each, in its numbering (models
# 261 to 280 were never part of it). The names are those of the shared
# CATEGORIES.tsv, which bench/psb_benchmark.py's articulated list uses.
CATEGORY_NAMES = ["Human", "Cup", "Glasses", "Airplane", "Ant", "Chair", "Octopus", "Table",
                  "Teddy", "Hand", "Plier", "Fish", "Bird", None, "Armadillo", "Bust", "Mech",
                  "Bearing", "Vase", "FourLeg"]


def category_of(model):
    """The benchmark category of model number `model` (1-based), or None."""
    index = (model - 1) // 20
    return CATEGORY_NAMES[index] if 0 <= index < len(CATEGORY_NAMES) else None


def off_face_count(path):
    """Face count of an OFF file, read from its header; raises ValueError."""
    tokens = []
    with open(path, "rb") as f:
        for raw in f:
            line = raw.split(b"#", 1)[0].strip()
            if not line:
                continue
            if not tokens and line.startswith(b"OFF"):
                line = line[3:].strip()
                tokens.append(b"OFF")
                if not line:
                    continue
            if not tokens:
                raise ValueError("does not start with OFF")
            tokens.extend(line.split())
            if len(tokens) >= 4:
                break
    if len(tokens) < 4:
        raise ValueError("has no vertex and face counts")
    try:
        return int(tokens[2])
    except ValueError:
        raise ValueError(f"face count '{tokens[2].decode(errors='replace')}' is not a number")


def shared_models(shared_data):
    folder = Path(shared_data) / "psb" / "off"
    if not folder.is_dir():
        return set()
    return {int(p.stem) for p in folder.glob("*.off") if p.stem.isdigit()}


def find_data_folder(benchmark):
    """The folder holding off/ and seg/: BENCHMARK/data or BENCHMARK itself."""
    for candidate in (Path(benchmark) / "data", Path(benchmark)):
        if (candidate / "off").is_dir():
            return candidate
    return None


def lay_out(benchmark, out, shared_data, models=None, log=print):
    """Writes the held-out layout; returns the model numbers written."""
    data = find_data_folder(benchmark)
    if data is None:
        raise FileNotFoundError(f"{benchmark}: no data/off folder (expected the benchmark's "
                                "MeshsegBenchmark-1.0 layout: data/off/N.off, data/seg/Benchmark/N/N_k.seg)")
    seg_root = data / "seg" / "Benchmark"
    skip = shared_models(shared_data)
    psb = Path(out) / "psb"
    written = []
    rows = []
    meshes = sorted((p for p in (data / "off").glob("*.off") if p.stem.isdigit()),
                    key=lambda p: int(p.stem))
    for mesh in meshes:
        model = int(mesh.stem)
        if model in skip or (models is not None and model not in models):
            continue
        category = category_of(model)
        if category is None:
            log(f"{mesh}: model {model} has no benchmark category, left out")
            continue
        try:
            faces = off_face_count(mesh)
        except (OSError, ValueError) as error:
            log(f"{mesh}: {error}, left out")
            continue
        humans = sorted((seg_root / str(model)).glob(f"{model}_*.seg"))
        if not humans:
            log(f"{mesh}: no human segmentation in {seg_root / str(model)}, left out")
            continue
        problem = None
        for human in humans:
            try:
                labels = len(read_labels(human))
            except (OSError, ValueError) as error:
                problem = f"{human}: {error}"
                break
            if labels != faces:
                problem = f"{human}: {labels} labels for {faces} faces"
                break
        if problem:
            log(f"{problem}, model {model} left out")
            continue
        (psb / "off").mkdir(parents=True, exist_ok=True)
        target = psb / "seg" / str(model)
        target.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(mesh, psb / "off" / mesh.name)
        for human in humans:
            with open(human, "rb") as source, gzip.open(target / (human.name + ".gz"), "wb") as sink:
                shutil.copyfileobj(source, sink)
        written.append(model)
        rows.append(f"{model}\t{category}\n")
    if written:
        (psb / "CATEGORIES.tsv").write_text("".join(rows))
    return written


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--benchmark", required=True,
                   help="the benchmark copy (MeshsegBenchmark-1.0, or its data/ folder)")
    p.add_argument("--out", required=True, help="folder to write psb/ into (outside the repository)")
    p.add_argument("--shared", default=str(REPO.parent / "shared" / "data"),
                   help="the shared data folder whose psb/off models are left out "
                        "(default: ../shared/data next to the repository)")
    p.add_argument("--models", default=None, help='only these model numbers, e.g. "4,5,84"')
    return p.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    out = Path(args.out).resolve()
    if out == REPO or REPO in out.parents:
        print(f"heldout_psb: {args.out}: inside the repository; write the models elsewhere",
              file=sys.stderr)
        return 2
    models = None
    if args.models:
        try:
            models = {int(m) for m in args.models.split(",") if m.strip()}
        except ValueError:
            print(f"heldout_psb: --models '{args.models}': not a list of numbers", file=sys.stderr)
            return 2
    try:
        written = lay_out(args.benchmark, out, args.shared, models,
                          log=lambda line: print(line, file=sys.stderr))
    except FileNotFoundError as error:
        print(f"heldout_psb: {error}", file=sys.stderr)
        return 2
    categories = {}
    for model in written:
        categories[category_of(model)] = categories.get(category_of(model), 0) + 1
    summary = ", ".join(f"{name} {count}" for name, count in sorted(categories.items()))
    print(f"wrote {len(written)} models to {out / 'psb'}" + (f" ({summary})" if summary else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
