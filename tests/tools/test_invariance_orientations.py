"""bench/invariance.py --orientations: the turned, mirrored and reordered copies, and the table.

The sweep runs a stand-in for skelseg that labels each face by which side of
x = 0.5 its centre lies on, so what each placement should give is known."""
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

# Four triangles, each on its own corners, with centres at x = 1, 1, 0, 0 and
# y = 1, 0, 1, 0 (z = 0): written as OFF with comments and a quad-free body.
OFF = """OFF
# four triangles
12 4 0
0.5 0.5 0\n1.5 0.5 0\n1 2 0
0.5 -0.5 0\n1.5 -0.5 0\n1 1 0
-0.5 0.5 0\n0.5 0.5 0\n0 2 0
-0.5 -0.5 0\n0.5 -0.5 0\n0 1 0
3 0 1 2
3 3 4 5
3 6 7 8
3 9 10 11
"""


def test_turned_and_mirrored_copies_are_exact_and_keep_the_face_order(tmp_path):
    mesh = tmp_path / "m.off"
    mesh.write_text(OFF)
    vertices, faces = invariance.read_polygons(mesh)
    assert len(vertices) == 12 and faces[1] == [3, 4, 5]
    turned = invariance.read_polygons(invariance.write_oriented(mesh, "rz", tmp_path / "rz.obj")[0])
    # A quarter turn about z: (x, y, z) -> (-y, x, z), the file's own digits.
    assert turned[0][1] == ["-0.5", "1.5", "0"] and turned[0][3] == ["0.5", "0.5", "0"]
    assert turned[1] == faces
    mirrored = invariance.read_polygons(invariance.write_oriented(mesh, "mx", tmp_path / "mx.obj")[0])
    assert mirrored[0][1] == ["-1.5", "0.5", "0"] and mirrored[0][6] == ["0.5", "0.5", "0"]
    assert mirrored[1] == [f[::-1] for f in faces]  # still facing out
    about_x = invariance.read_polygons(invariance.write_oriented(mesh, "rx", tmp_path / "rx.obj")[0])
    assert about_x[0][2] == ["1", "-0", "2"]  # (x, y, z) -> (x, -z, y)
    # Another face order: the same vertices, each face of the copy one of
    # the original's, started at another corner, as the returned order says.
    path, order = invariance.write_oriented(mesh, "faces", tmp_path / "faces.obj")
    shuffled = invariance.read_polygons(path)
    assert shuffled[0] == vertices and sorted(order) == [0, 1, 2, 3]
    assert list(order) != [0, 1, 2, 3]
    for copy, original in zip(shuffled[1], order):
        assert copy != faces[original]
        assert any(copy == faces[original][r:] + faces[original][:r] for r in (1, 2))


FAKE_SKELSEG = """#!/usr/bin/python3
# Labels each face 1 where its centre has x > 0.5, else 0.
import json, pathlib, sys
sys.path.insert(0, %r)
import invariance
args = sys.argv[1:]
mesh, out = args[1], pathlib.Path(args[args.index("-o") + 1])
vertices, faces = invariance.read_polygons(mesh)
labels = [int(sum(float(vertices[c][0]) for c in f) / len(f) > 0.5) for f in faces]
out.mkdir(parents=True, exist_ok=True)
(out / "segmentation.seg").write_text("".join(f"{v}\\n" for v in labels))
(out / "report.json").write_text(json.dumps({"segment_count": len(set(labels)),
    "input": {"mesh_genus": 0, "voxel_genus": 0, "contacts_separated": 0}}))
"""


def test_each_placement_is_compared_face_for_face_with_the_mesh_as_it_lies(tmp_path):
    data = tmp_path / "data"
    (data / "shapes").mkdir(parents=True)
    (data / "shapes" / "m.off").write_text(OFF)
    fake = tmp_path / "skelseg"
    fake.write_text(FAKE_SKELSEG % str(ROOT / "bench"))
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    result = tmp_path / "sweep.json"
    run = subprocess.run([sys.executable, str(SCRIPT), "--skelseg", str(fake), "--data", str(data),
                          "--sequences", "none", "--shapes", "m.off", "--resolutions", "",
                          "--orientations", "rz,mx,mz,faces", "--jobs", "2", "--json", str(result)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    sweep = json.loads(result.read_text())
    assert sweep["resolutions"] == {}
    entry = sweep["orientations"]["m.off"]
    # As it lies: faces 0, 1 right of x = 0.5, faces 2, 3 left. Turned about z
    # or mirrored along x, every centre is at x <= 0: one part, and the 4 of
    # 6 face pairs split before now agree. Mirrored along z, nothing moves in x.
    # In another face order the labels, mapped back, are the same.
    assert entry["parts"] == 2 and entry["placed_parts"] == [1, 1, 2, 2]
    assert entry["ri_error"] == pytest.approx([4 / 6, 4 / 6, 0.0, 0.0])
    assert entry["identical"] == 2 and not entry["same_parts"]
    assert "| m.off | 2 | 1, 1, 2, 2 | 0.667, 0.667, 0.000, 0.000 | 2 of 4 |" in run.stdout


def test_an_unknown_placement_is_refused(tmp_path):
    (tmp_path / "data" / "shapes").mkdir(parents=True)
    fake = tmp_path / "skelseg"
    fake.write_text("#!/bin/sh\nexit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    run = subprocess.run([sys.executable, str(SCRIPT), "--skelseg", str(fake), "--data",
                          str(tmp_path / "data"), "--sequences", "none", "--shapes", "",
                          "--orientations", "rz,tilt"], capture_output=True, text=True)
    assert run.returncode == 2
    assert "unknown placement 'tilt'" in run.stderr
