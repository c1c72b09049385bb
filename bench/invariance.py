#!/usr/bin/python3
"""Pose and resolution invariance of skelseg's segmentations (issue 12).

Pose sequences: every mesh DATA/poses/NAME_FRAME.obj (grouped by the prefix
before the last "_", frames in numeric order) is segmented with

    skelseg segment MESH -o OUT/... --resolution R -q --no-preview --force

(defaults otherwise, as a new user would). All frames of a sequence have the
same faces in the same order, so their face labels compare directly: the
table gives the parts per frame (distinct labels in segmentation.seg) and the
mean Rand Index error over all pairs of frames (1 - RI, face pairs counted
once each, as `skelseg score` does).

Resolutions: a few meshes of DATA/shapes, and with --psb the models of the
Princeton benchmark in DATA/psb/off, are segmented at 128, 192, 256 and 320;
the same measures compare the resolutions of one mesh (the faces are the
same, only the voxel model changes).

    /usr/bin/python3 bench/invariance.py                      # markdown table
    /usr/bin/python3 bench/invariance.py --json out.json      # and every number
    /usr/bin/python3 bench/invariance.py --skelseg /tmp/old/skelseg --shapes hand.off
    /usr/bin/python3 bench/invariance.py --sequences none --shapes "" --psb all --jobs 2

Orientations (--orientations rz,mx or all): the same meshes (--shapes, and
the first frame of each pose sequence) turned a quarter turn about an axis
(rx, ry, rz: exact, coordinates swapped and negated) or mirrored along one
(mx, my, mz: the faces' corners reversed so they still face out), written as
OBJ files with the faces in their order, are segmented at --pose-resolution
and compared face for face with the mesh as it lies. A user expects the same
parts from a scan however it lies; the table says how far that holds. The
placement "faces" keeps the geometry and writes the faces in another order
(a fixed shuffle), each started at another corner, as another exporter
might; its labels are mapped back to the original faces.

Where DATA is absent it says so and exits 0. A run that skelseg refuses or
fails (a flat mesh, a broken file: skelseg exits non-zero) does not stop the
others: its sequence, mesh or placement is listed as failed with skelseg's
message, counts as not keeping its part count, and is left out of the mean
error; the tables and --json are written, and the exit code is then 1.
Needs numpy.
"""

import argparse
import concurrent.futures
import itertools
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from psb_benchmark import ARTICULATED, read_categories  # noqa: E402  (one list of categories)

REPO = Path(__file__).resolve().parent.parent
DEFAULT_SHAPES = ["camel.off", "hand.off", "horse.off", "octopus.off"]


def binary_and_data_parser(doc):
    """An argument parser for a script documented by `doc`, with --skelseg
    and --data (bench/sequence_consensus.py shares it)."""
    p = argparse.ArgumentParser(description=doc.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=doc.split("\n\n", 1)[1])
    p.add_argument("--skelseg", default=str(REPO / "build" / "skelseg"),
                   help="the skelseg binary (default: build/skelseg in the repository)")
    p.add_argument("--data", default=str(REPO.parent / "shared" / "data"),
                   help="the shared data folder (default: ../shared/data next to the repository)")
    return p


def parse_args(argv):
    p = binary_and_data_parser(__doc__)
    p.add_argument("--pose-resolution", type=int, default=192,
                   help="resolution for the pose sequences (default 192)")
    p.add_argument("--pose-grid", choices=["frame", "largest", "smallest"], default="frame",
                   help="voxel size of the pose frames: 'frame' (default) gives each frame "
                        "--pose-resolution voxels along its own longest side; 'largest' and "
                        "'smallest' give every frame of a sequence one voxel size, that of its "
                        "frame with the largest or smallest bounding box at --pose-resolution")
    p.add_argument("--resolutions", default="128,192,256,320",
                   help="comma-separated resolutions for the shapes (default 128,192,256,320; "
                        "empty: no resolution sweep)")
    p.add_argument("--shapes", default=",".join(DEFAULT_SHAPES),
                   help="comma-separated files of DATA/shapes (default %(default)s); empty: none")
    p.add_argument("--sequences", default="",
                   help="comma-separated pose sequence names (default: every one; 'none': none)")
    p.add_argument("--psb", default="",
                   help="PSB models to sweep over the resolutions: 'all', 'articulated', "
                        "category names or model numbers, comma-separated (default: none)")
    p.add_argument("--orientations", default="",
                   help="comma-separated placements to compare with the mesh as it lies: "
                        "rx, ry, rz (quarter turns), mx, my, mz (mirrors), faces (another "
                        "face order), or 'all' (default: none)")
    p.add_argument("--jobs", type=int, default=1,
                   help="segmentations run side by side (default 1; the seconds are then "
                        "inflated, the labels are not)")
    p.add_argument("--workdir", default=None,
                   help="keep the segmentations here (default: a temporary folder)")
    p.add_argument("--json", default=None, help="write every number to this JSON file")
    return p.parse_args(argv)


def read_labels(path):
    """A .seg file: one integer label per line (line i = face i)."""
    return np.loadtxt(path, dtype=np.int64, ndmin=1)


def rand_index_error(a, b):
    """1 - Rand Index of two labelings of the same faces, every face once."""
    if a.shape != b.shape:
        raise ValueError(f"different face counts: {a.size} and {b.size}")
    n = a.size
    if n < 2:
        return 0.0
    _, ia = np.unique(a, return_inverse=True)
    _, ib = np.unique(b, return_inverse=True)
    pairs = lambda c: float(np.sum(c.astype(np.float64) * (c - 1)) / 2.0)
    joint = np.unique(ia.astype(np.int64) * (ib.max() + 1) + ib, return_counts=True)[1]
    disagree = pairs(np.bincount(ia)) + pairs(np.bincount(ib)) - 2.0 * pairs(joint)
    return disagree / (n * (n - 1) / 2.0)


class RunFailed(RuntimeError):
    """skelseg exited non-zero on one input; the message names it and says why."""


def segment(skelseg, mesh, out, resolution):
    cmd = [skelseg, "segment", str(mesh), "-o", str(out), "--resolution", str(resolution),
           "-q", "--no-preview", "--force"]
    start = time.monotonic()
    run = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.monotonic() - start
    if run.returncode != 0:
        lines = (run.stderr or run.stdout).strip().splitlines()
        raise RunFailed(f"{mesh}: skelseg exited {run.returncode}: "
                           f"{lines[-1] if lines else 'no message'}")
    labels = read_labels(out / "segmentation.seg")
    report = json.loads((out / "report.json").read_text())
    return {"labels": labels, "parts": int(np.unique(labels).size), "seconds": seconds,
            "segment_count": report.get("segment_count"),
            "mesh_genus": report.get("input", {}).get("mesh_genus"),
            "voxel_genus": report.get("input", {}).get("voxel_genus"),
            "contacts_separated": report.get("input", {}).get("contacts_separated")}


ORIENTATIONS = ("rx", "ry", "rz", "mx", "my", "mz", "faces")


def read_polygons(mesh):
    """Vertex coordinates (as the file's text, three per vertex) and faces
    (0-based corner lists) of an .obj or .off file, faces in file order."""
    text = Path(mesh).read_text(errors="replace").split("\n")
    if Path(mesh).suffix.lower() == ".off":
        body = [t for t in (line.split("#")[0].split() for line in text) if t]
        header = 1 if body[0][0].upper().endswith("OFF") and len(body[0]) == 1 else 0
        counts = body[header] if header else body[0][1:]
        first = header + 1
        vertices = [t[:3] for t in body[first:first + int(counts[0])]]
        faces = [[int(i) for i in t[1:1 + int(t[0])]]
                 for t in body[first + int(counts[0]):first + int(counts[0]) + int(counts[1])]]
        return vertices, faces
    vertices, faces = [], []
    for line in text:
        if line.startswith("v "):
            vertices.append(line.split()[1:4])
        elif line.startswith("f "):
            corners = [int(c.split("/")[0]) for c in line.split()[1:]]
            faces.append([c - 1 if c > 0 else len(vertices) + c for c in corners])
    return vertices, faces


def negated(number):
    return number[1:] if number.startswith("-") else "-" + number


def write_oriented(mesh, placement, out):
    """MESH turned (rx, ry, rz: a quarter turn about that axis) or mirrored
    (mx, my, mz), written to OUT as OBJ with the faces in the same order. The
    coordinates are the file's own numbers, swapped and negated, so the
    placement is exact. "faces": the same vertices, the faces shuffled (a
    permutation fixed by the face count) and each rotated by one or two
    corners. Returns the path and, per face of the copy, the index of the
    original face it is."""
    vertices, faces = read_polygons(mesh)
    order = np.arange(len(faces))
    if placement == "faces":
        order = np.random.default_rng(len(faces)).permutation(len(faces))
        faces = [faces[k][1 + i % 2:] + faces[k][:1 + i % 2] for i, k in enumerate(order)]
    lines = []
    for v in vertices:
        v = list(v)
        if placement == "faces":
            pass
        elif placement[0] == "m":
            axis = "xyz".index(placement[1])
            v[axis] = negated(v[axis])
        else:  # a quarter turn: (a, b) -> (-b, a) in the plane of the two other axes
            a, b = [k for k in range(3) if k != "xyz".index(placement[1])]
            v[a], v[b] = negated(v[b]), v[a]
        lines.append("v " + " ".join(v))
    for f in faces:
        corners = f[::-1] if placement[0] == "m" else f
        lines.append("f " + " ".join(str(c + 1) for c in corners))
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    Path(out).write_text("\n".join(lines) + "\n")
    return Path(out), order


def longest_side(mesh):
    """The longest side of a mesh's bounding box (vertices of .obj or .off only)."""
    text = Path(mesh).read_text(errors="replace").split("\n")
    if Path(mesh).suffix.lower() == ".off":
        body = [line.split("#")[0].split() for line in text]
        body = [t for t in body if t]
        header = 1 if body[0][0].upper().endswith("OFF") and len(body[0]) == 1 else 0
        counts = body[header] if header else body[0][1:]
        points = [list(map(float, t[:3])) for t in body[header + 1:header + 1 + int(counts[0])]]
    else:
        points = [list(map(float, line.split()[1:4])) for line in text if line.startswith("v ")]
    points = np.asarray(points)
    return float((points.max(axis=0) - points.min(axis=0)).max())


def frame_resolutions(frames, resolution, grid):
    """Per-frame --resolution for --pose-grid: one voxel size across a sequence unless 'frame'."""
    if grid == "frame":
        return [resolution] * len(frames)
    sides = [longest_side(f) for f in frames]
    voxel = (max(sides) if grid == "largest" else min(sides)) / resolution
    return [max(8, int(round(side / voxel))) for side in sides]


def compare(runs):
    """Parts per run and the mean pairwise Rand Index error."""
    errors = [rand_index_error(a["labels"], b["labels"]) for a, b in itertools.combinations(runs, 2)]
    return {"parts": [r["parts"] for r in runs],
            "same_parts": len({r["parts"] for r in runs}) == 1,
            "mean_ri_error": float(np.mean(errors)) if errors else 0.0,
            "max_ri_error": float(np.max(errors)) if errors else 0.0,
            "voxel_genus": [r["voxel_genus"] for r in runs],
            "mesh_genus": [r["mesh_genus"] for r in runs],
            "contacts_separated": [r["contacts_separated"] for r in runs],
            "seconds": [round(r["seconds"], 2) for r in runs]}


def pose_sequences(poses):
    groups = {}
    for path in sorted(poses.glob("*.obj")) + sorted(poses.glob("*.off")):
        name, _, frame = path.stem.rpartition("_")
        if not name:
            continue
        key = int(frame) if re.fullmatch(r"\d+", frame) else frame
        groups.setdefault(name, []).append((key, path))
    return {name: [p for _, p in sorted(frames, key=lambda f: (str(type(f[0])), f[0]))]
            for name, frames in sorted(groups.items())}


def psb_models(psb, selection):
    """The (model number, category) pairs that SELECTION names, in model order."""
    categories = read_categories(psb)
    chosen = set()
    for item in [w.strip() for w in selection.split(",") if w.strip()]:
        if item == "all":
            chosen |= set(categories)
        elif item == "articulated":
            chosen |= {m for m, c in categories.items() if c in ARTICULATED}
        elif item.isdigit():
            if int(item) not in categories:
                raise ValueError(f"PSB model {item} is not in {psb / 'CATEGORIES.tsv'}")
            chosen.add(int(item))
        else:
            named = {m for m, c in categories.items() if c.lower() == item.lower()}
            if not named:
                raise ValueError(f"no PSB category or model '{item}' in {psb / 'CATEGORIES.tsv'}")
            chosen |= named
    return [(m, categories[m]) for m in sorted(chosen)]


def fmt_list(values):
    return ", ".join("?" if v is None else str(v) for v in values)


def fmt_set(values):
    """The distinct values (the mesh genus is the same for every frame)."""
    return fmt_list(sorted({v for v in values if v is not None}) or [None])


def failed(failure):
    """The entry of a sequence, mesh or placement one of whose runs failed."""
    return {"failed": str(failure), "same_parts": False}


def summary(entry):
    if "failed" in entry:
        return f"failed: {entry['failed']}"
    return f"parts {fmt_list(entry['parts'])}, mean RI error {entry['mean_ri_error']:.3f}"


def failures_note(entries):
    count = sum("failed" in e for e in entries.values())
    return f" ({count} failed)" if count else ""


def mean_error(entries):
    """The mean of the measured entries' errors, saying over how many when some failed."""
    errors = [e["mean_ri_error"] for e in entries.values() if "failed" not in e]
    if not errors:
        return "not measured"
    text = f"{np.mean(errors):.3f}"
    return text if len(errors) == len(entries) else f"{text} (over the {len(errors)} measured)"


def main(argv):
    args = parse_args(argv)
    skelseg = Path(args.skelseg)
    data = Path(args.data)
    if not skelseg.exists():
        print(f"invariance.py: error: {skelseg}: no such binary", file=sys.stderr)
        return 2
    if not data.is_dir():
        print(f"invariance.py: {data}: no shared data; nothing measured")
        return 0
    workdir_holder = None
    if args.workdir:
        work = Path(args.workdir)
        work.mkdir(parents=True, exist_ok=True)
    else:
        workdir_holder = tempfile.TemporaryDirectory(prefix="skelseg-invariance-")
        work = Path(workdir_holder.name)

    results = {"skelseg": str(skelseg), "pose_resolution": args.pose_resolution,
               "pose_grid": args.pose_grid,
               "sequences": {}, "resolutions": {}}
    wanted = {s for s in args.sequences.split(",") if s}
    for name, frames in pose_sequences(data / "poses").items() if (data / "poses").is_dir() else []:
        if wanted and name not in wanted or "none" in wanted:
            continue
        grids = frame_resolutions(frames, args.pose_resolution, args.pose_grid)
        try:
            entry = compare([segment(skelseg, f, work / "poses" / f.stem, r)
                             for f, r in zip(frames, grids)])
        except RunFailed as failure:
            entry = failed(failure)
        entry["frames"] = [f.stem.rpartition("_")[2] for f in frames]
        entry["frame_resolutions"] = grids
        results["sequences"][name] = entry
        print(f"{name}: {summary(entry)}", file=sys.stderr)

    resolutions = [int(r) for r in args.resolutions.split(",") if r]
    sweeps = []  # (key, mesh, out stem, table)
    for shape in [s for s in args.shapes.split(",") if s]:
        mesh = data / "shapes" / shape
        if not mesh.exists():
            print(f"invariance.py: {mesh}: missing, skipped", file=sys.stderr)
            continue
        sweeps.append((shape, mesh, work / "shapes" / mesh.stem, "resolutions"))
    if args.psb:
        psb = data / "psb"
        try:
            models = psb_models(psb, args.psb) if (psb / "CATEGORIES.tsv").exists() else []
        except ValueError as error:
            print(f"invariance.py: error: {error}", file=sys.stderr)
            return 2
        if not models:
            print(f"invariance.py: {psb}: no PSB models; none swept", file=sys.stderr)
        for model, category in models:
            mesh = psb / "off" / f"{model}.off"
            if mesh.exists():
                sweeps.append((f"{model} ({category})", mesh, work / "psb" / str(model), "psb"))
    results["psb"] = {}
    placements = list(ORIENTATIONS) if args.orientations == "all" else \
        [o for o in args.orientations.split(",") if o]
    unknown = [o for o in placements if o not in ORIENTATIONS]
    if unknown:
        print(f"invariance.py: error: --orientations: unknown placement '{unknown[0]}' "
              f"(known: {', '.join(ORIENTATIONS)}, all)", file=sys.stderr)
        return 2
    results["orientations"] = {}
    turned = []  # (key, mesh): the shapes, and the first frame of each sequence
    if placements:
        turned = [(s, m) for s, m, _, table in sweeps if table == "resolutions"]
        for name, frames in pose_sequences(data / "poses").items() if (data / "poses").is_dir() \
                else []:
            if not (wanted and name not in wanted or "none" in wanted):
                turned.append((frames[0].name, frames[0]))
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        placed = {}
        for key, mesh in turned:
            stem = work / "orientations" / Path(key).stem
            placed[(key, "")] = pool.submit(segment, skelseg, mesh, stem, args.pose_resolution)
            for o in placements:
                copy, order = write_oriented(mesh, o, work / "orientations" / "meshes" /
                                             f"{Path(key).stem}-{o}.obj")
                placed[(key, o)] = (pool.submit(segment, skelseg, copy, Path(f"{stem}-{o}"),
                                                args.pose_resolution), order)
        futures = {(key, r): pool.submit(segment, skelseg, mesh, Path(f"{stem}-{r}"), r)
                   for key, mesh, stem, _ in sweeps for r in resolutions}
        for key, mesh, stem, table in sweeps if resolutions else []:
            try:
                entry = compare([futures[(key, r)].result() for r in resolutions])
            except RunFailed as failure:
                entry = failed(failure)
            entry["resolution"] = resolutions
            results[table][key] = entry
            print(f"{key}: {summary(entry)}", file=sys.stderr)
        for key, _ in turned:
            try:
                original = placed[(key, "")].result()
                runs = []
                for o in placements:
                    future, order = placed[(key, o)]
                    run = dict(future.result())
                    if run["labels"].size == order.size:  # back to the original faces
                        labels = np.empty_like(run["labels"])
                        labels[order] = run["labels"]
                        run["labels"] = labels
                    runs.append(run)
            except RunFailed as failure:
                results["orientations"][key] = dict(failed(failure), placements=placements)
                print(f"{key}: failed: {failure}", file=sys.stderr)
                continue
            errors = [rand_index_error(original["labels"], r["labels"]) for r in runs]
            results["orientations"][key] = {
                "placements": placements, "parts": original["parts"],
                "placed_parts": [r["parts"] for r in runs],
                "same_parts": all(r["parts"] == original["parts"] for r in runs),
                "ri_error": errors, "mean_ri_error": float(np.mean(errors)),
                "identical": sum(bool(np.array_equal(original["labels"], r["labels"]))
                                 for r in runs)}
            print(f"{key}: parts {original['parts']}, placed "
                  f"{fmt_list(results['orientations'][key]['placed_parts'])}", file=sys.stderr)

    lines = []
    if results["sequences"]:
        grid_note = ("" if args.pose_grid == "frame" else
                     f"; one voxel size per sequence, that of its {args.pose_grid} frame")
        lines += [f"Pose sequences (resolution {args.pose_resolution}{grid_note}):", "",
                  "| sequence | frames | parts per frame | mean RI error between frames "
                  "| voxel genus per frame (mesh genus) | contacts separated |",
                  "| --- | --- | --- | --- | --- | --- |"]
        for name, e in results["sequences"].items():
            frames = fmt_list(e["frames"])
            if args.pose_grid != "frame":
                frames += f" (at {fmt_list(e['frame_resolutions'])})"
            if "failed" in e:
                lines.append(f"| {name} | {frames} | failed: {e['failed']} | | | |")
                continue
            lines.append(f"| {name} | {frames} | {fmt_list(e['parts'])} | "
                         f"{e['mean_ri_error']:.3f} | {fmt_list(e['voxel_genus'])} "
                         f"({fmt_set(e['mesh_genus'])}) | "
                         f"{fmt_list(e['contacts_separated'])} |")
        same = sum(e["same_parts"] for e in results["sequences"].values())
        lines += ["", f"Same part count in every frame: {same} of {len(results['sequences'])} "
                  f"sequences{failures_note(results['sequences'])}; mean RI error between "
                  f"frames {mean_error(results['sequences'])}.", ""]
    for table, title, plural in (("resolutions", "mesh", "meshes"),
                                 ("psb", "PSB model", "PSB models")):
        if not results[table]:
            continue
        lines += [f"Resolutions {fmt_list(resolutions)}:", "",
                  f"| {title} | parts per resolution | mean RI error between resolutions "
                  "| voxel genus (mesh genus) | contacts separated |",
                  "| --- | --- | --- | --- | --- |"]
        for name, e in results[table].items():
            if "failed" in e:
                lines.append(f"| {name} | failed: {e['failed']} | | | |")
                continue
            lines.append(f"| {name} | {fmt_list(e['parts'])} | {e['mean_ri_error']:.3f} | "
                         f"{fmt_list(e['voxel_genus'])} "
                         f"({fmt_set(e['mesh_genus'])}) | "
                         f"{fmt_list(e['contacts_separated'])} |")
        same = sum(e["same_parts"] for e in results[table].values())
        lines += ["", f"Same part count at every resolution: {same} of "
                  f"{len(results[table])} {plural}{failures_note(results[table])}; mean RI "
                  f"error {mean_error(results[table])}.", ""]
    if results["orientations"]:
        lines += [f"Orientations (resolution {args.pose_resolution}), each against the mesh "
                  "as it lies:", "",
                  f"| mesh | parts | parts {', '.join(placements)} | RI error to the mesh as "
                  "it lies | same labels |", "| --- | --- | --- | --- | --- |"]
        for name, e in results["orientations"].items():
            if "failed" in e:
                lines.append(f"| {name} | failed: {e['failed']} | | | |")
                continue
            lines.append(f"| {name} | {e['parts']} | {fmt_list(e['placed_parts'])} | "
                         f"{', '.join(f'{x:.3f}' for x in e['ri_error'])} | "
                         f"{e['identical']} of {len(placements)} |")
        same = sum(e["same_parts"] for e in results["orientations"].values())
        lines += ["", f"Same part count in every placement: {same} of "
                  f"{len(results['orientations'])} meshes"
                  f"{failures_note(results['orientations'])}; mean RI error to the mesh as it "
                  f"lies {mean_error(results['orientations'])}.", ""]
    print("\n".join(lines))
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2) + "\n")
    tables = ("sequences", "resolutions", "psb", "orientations")
    return 1 if any("failed" in e for t in tables for e in results[t].values()) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
