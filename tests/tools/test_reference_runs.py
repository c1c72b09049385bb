"""bench/reference_runs.py: a model skelseg refuses is a row, not the end of the
run; with --compare-exhaustive the outputs of the two searches are compared.

A stand-in skelseg writes the report and outputs, so what is checked is the
script's bookkeeping against answers we chose, not the engine's."""
import json
import pathlib
import shutil
import stat
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "bench" / "reference_runs.py"
sys.path.insert(0, str(ROOT / "bench"))
import reference_runs  # noqa: E402

FAKE_SKELSEG = """#!/usr/bin/python3
# Refuses meshes named "flat*" (exit 2, one line); otherwise writes a report
# and outputs. The exhaustive search labels mesh "split*" differently.
import json, pathlib, sys
args = sys.argv[1:]
mesh = pathlib.Path(args[1])
if mesh.name.startswith("flat"):
    print(f"skelseg: error: {mesh}: the mesh is flat", file=sys.stderr)
    sys.exit(2)
out = pathlib.Path(args[args.index("-o") + 1])
out.mkdir(parents=True, exist_ok=True)
exhaustive = "exhaustive" in args
labels = [0, 0, 1, 1] if exhaustive and mesh.name.startswith("split") else [0, 0, 0, 1]
(out / "segmentation.seg").write_text("".join(f"{v}\\n" for v in labels))
for name in ("skeleton.ply", "cuts.ply", "labels.nrrd"):
    (out / name).write_text("same")
(out / "report.json").write_text(json.dumps({
    "timing": {"cpu_seconds": 1.0, "serial_share": 0.1}, "segment_count": len(set(labels)),
    "stages": [{"name": "path sets, rims, areas, sigma", "wall_seconds": 0.01}],
    "work": {"nodes_settled": 10}}))
"""


@pytest.mark.skipif(not pathlib.Path("/usr/bin/time").exists(), reason="needs /usr/bin/time")
def test_a_refused_model_is_a_row_and_the_searches_outputs_are_compared(tmp_path):
    shapes = tmp_path / "data" / "shapes"
    shapes.mkdir(parents=True)
    for name in ("flat.off", "good.off", "split.off", "notes.txt"):
        (shapes / name).write_text("OFF\n")
    fake = tmp_path / "skelseg"
    fake.write_text(FAKE_SKELSEG)
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, str(SCRIPT), "--skelseg", str(fake), "--data",
                          str(tmp_path / "data"), "--models", "all", "--resolutions", "64",
                          "--repeat", "1", "--compare-exhaustive", "--out", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    assert "| flat.off | 64 | failed: exit 2: skelseg: error: " in run.stdout
    assert "notes.txt" not in run.stdout  # not a mesh
    record = {r["mesh"]: r for r in json.loads((out / "reference.json").read_text())}
    assert "the mesh is flat" in record["flat.off"]["failed"]
    assert all(record["good.off"]["same_outputs"].values())
    assert record["split.off"]["same_outputs"]["segmentation.seg"] is False
    # Faces 2 and 3 together against 0, 1, 2 together: 3 of the 6 face pairs disagree.
    assert record["split.off"]["ri_error"] == pytest.approx(0.5)
    assert "| identical |" in run.stdout
    assert "differ: segmentation.seg; parts 2 / 2; RI error 0.5000" in run.stdout


def test_labels_are_compared_face_pair_by_face_pair(tmp_path):
    def outputs(name, labels):
        folder = tmp_path / name
        folder.mkdir()
        (folder / "segmentation.seg").write_text("".join(f"{v}\n" for v in labels))
        return folder

    same, ri = reference_runs.same_outputs(outputs("a", [0, 0, 1, 1]), outputs("b", [5, 5, 7, 7]))
    assert same == {"segmentation.seg": False} and ri == 0.0  # other ids, same parts
    _, ri = reference_runs.same_outputs(outputs("c", [0, 0, 0, 1]), outputs("d", [0, 0, 1, 1]))
    assert ri == pytest.approx(0.5)
    _, ri = reference_runs.same_outputs(outputs("e", [0, 1]), outputs("f", [0, 1, 2]))
    assert ri == 1.0  # other face counts: nothing compares
