"""bench/invariance.py --psb: which models a selection names, and the resolution sweep's table.

The sweep runs a stand-in for skelseg (a script that labels the faces by the
resolution it is given), so the comparison of resolutions is checked against
labels we chose, not against the engine's current answers."""
import json
import pathlib
import stat
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "bench" / "invariance.py"
sys.path.insert(0, str(ROOT / "bench"))
np = pytest.importorskip("numpy")
import invariance  # noqa: E402

CATEGORIES = "1\tHuman\n2\tHuman\n21\tCup\n81\tAnt\n301\tBust\n"


def psb_folder(root: pathlib.Path) -> pathlib.Path:
    psb = root / "psb"
    (psb / "off").mkdir(parents=True)
    (psb / "CATEGORIES.tsv").write_text(CATEGORIES)
    for model in (1, 2, 21, 81, 301):
        (psb / "off" / f"{model}.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    return psb


def test_selections_name_models_by_number_category_and_group(tmp_path):
    psb = psb_folder(tmp_path)
    assert invariance.psb_models(psb, "all") == [(1, "Human"), (2, "Human"), (21, "Cup"),
                                                 (81, "Ant"), (301, "Bust")]
    assert invariance.psb_models(psb, "articulated") == [(1, "Human"), (2, "Human"), (81, "Ant")]
    assert invariance.psb_models(psb, "cup,301,1") == [(1, "Human"), (21, "Cup"), (301, "Bust")]
    with pytest.raises(ValueError, match="'Chair'"):
        invariance.psb_models(psb, "Chair")
    with pytest.raises(ValueError, match="PSB model 5 "):
        invariance.psb_models(psb, "5")


FAKE_SKELSEG = """#!/usr/bin/python3
# Writes 10 face labels: at resolution 128 two parts, above it three, the
# third taken from the first part's last two faces.
import json, pathlib, sys
args = sys.argv[1:]
out = pathlib.Path(args[args.index("-o") + 1])
resolution = int(args[args.index("--resolution") + 1])
labels = [0] * 5 + [1] * 5
if resolution > 128:
    labels[3] = labels[4] = 2
out.mkdir(parents=True, exist_ok=True)
(out / "segmentation.seg").write_text("".join(f"{v}\\n" for v in labels))
(out / "report.json").write_text(json.dumps({"segment_count": len(set(labels)),
    "input": {"mesh_genus": 0, "voxel_genus": 0, "contacts_separated": 0}}))
"""


def test_the_psb_sweep_compares_the_resolutions_of_each_model(tmp_path):
    data = tmp_path / "data"
    psb_folder(data)
    fake = tmp_path / "skelseg"
    fake.write_text(FAKE_SKELSEG)
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    result = tmp_path / "sweep.json"
    run = subprocess.run([sys.executable, str(SCRIPT), "--skelseg", str(fake), "--data", str(data),
                          "--sequences", "none", "--shapes", "", "--psb", "Human,21",
                          "--resolutions", "128,192,256", "--jobs", "2", "--json", str(result)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    sweep = json.loads(result.read_text())
    assert sweep["sequences"] == {} and sweep["resolutions"] == {}
    assert list(sweep["psb"]) == ["1 (Human)", "2 (Human)", "21 (Cup)"]
    entry = sweep["psb"]["1 (Human)"]
    assert entry["parts"] == [2, 3, 3] and not entry["same_parts"]
    # 128 against either other resolution: faces 3 and 4 leave the group of
    # 0, 1 and 2, so 2 * 3 = 6 of the 45 face pairs disagree; 192 and 256 agree.
    assert entry["mean_ri_error"] == pytest.approx((6 / 45 + 6 / 45 + 0) / 3)
    assert "| 1 (Human) | 2, 3, 3 |" in run.stdout
    assert "Same part count at every resolution: 0 of 3 PSB models" in run.stdout


FAILING_SKELSEG = """#!/usr/bin/python3
# Refuses any mesh whose name holds "flat" (exit 2, one line naming it), as
# skelseg refuses a flat mesh; labels the others' 10 faces in two parts.
import json, pathlib, sys
args = sys.argv[1:]
mesh = args[1]
if "flat" in pathlib.Path(mesh).name:
    print(f"skelseg: error: {mesh}: the mesh is flat", file=sys.stderr)
    sys.exit(2)
out = pathlib.Path(args[args.index("-o") + 1])
out.mkdir(parents=True, exist_ok=True)
(out / "segmentation.seg").write_text("0\\n" * 5 + "1\\n" * 5)
(out / "report.json").write_text(json.dumps({"segment_count": 2,
    "input": {"mesh_genus": 0, "voxel_genus": 0, "contacts_separated": 0}}))
"""


def test_a_run_that_fails_is_listed_and_the_others_are_measured(tmp_path):
    data = tmp_path / "data"
    (data / "poses").mkdir(parents=True)
    (data / "shapes").mkdir()
    triangle = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    for name in ("walk_1.off", "walk_2.off", "flat_1.off", "flat_2.off"):
        (data / "poses" / name).write_text(triangle)
    for name in ("a.off", "flat.off"):
        (data / "shapes" / name).write_text(triangle)
    fake = tmp_path / "skelseg"
    fake.write_text(FAILING_SKELSEG)
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    result = tmp_path / "sweep.json"
    run = subprocess.run([sys.executable, str(SCRIPT), "--skelseg", str(fake), "--data", str(data),
                          "--shapes", "a.off,flat.off", "--resolutions", "128,192",
                          "--orientations", "rz", "--jobs", "2", "--json", str(result)],
                         capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    sweep = json.loads(result.read_text())
    assert sweep["sequences"]["walk"]["parts"] == [2, 2]
    assert "flat_1.off: skelseg exited 2" in sweep["sequences"]["flat"]["failed"]
    assert not sweep["sequences"]["flat"]["same_parts"]
    assert sweep["resolutions"]["a.off"]["same_parts"]
    assert "the mesh is flat" in sweep["resolutions"]["flat.off"]["failed"]
    assert "failed" in sweep["orientations"]["flat.off"]
    assert sweep["orientations"]["a.off"]["same_parts"]
    assert "| flat | 1, 2 | failed: " in run.stdout
    assert ("Same part count in every frame: 1 of 2 sequences (1 failed); mean RI error "
            "between frames 0.000 (over the 1 measured).") in run.stdout
    assert "Same part count at every resolution: 1 of 2 meshes (1 failed)" in run.stdout
    assert "flat: failed: " in run.stderr
