"""bench/compare_search.py: an input that skelseg refuses both ways is the same
answer; one that fails one way only is a difference; the others are still
compared. A stand-in skelseg gives answers we chose."""
import json
import pathlib
import stat
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "bench" / "compare_search.py"

FAKE_SKELSEG = """#!/usr/bin/python3
# "flat*": refused by both searches; "odd*": the band search fails; others:
# the same outputs both ways.
import json, pathlib, sys
args = sys.argv[1:]
mesh = pathlib.Path(args[1])
band = args[args.index("--skeleton-search") + 1] == "band"
if mesh.name.startswith("flat") or (band and mesh.name.startswith("odd")):
    print(f"skelseg: error: {mesh}: refused", file=sys.stderr)
    sys.exit(2)
out = pathlib.Path(args[args.index("-o") + 1])
out.mkdir(parents=True, exist_ok=True)
(out / "segmentation.seg").write_text("0\\n0\\n1\\n")
for name in ("skeleton.ply", "cuts.ply", "labels.nrrd"):
    (out / name).write_text("same")
(out / "report.json").write_text(json.dumps({
    "timing": {"cpu_seconds": 1.0}, "segment_count": 2,
    "stages": [{"name": "path sets, rims, areas, sigma", "cpu_seconds": 0.5, "wall_seconds": 0.3}],
    "counts": {"candidates": 100, "skeleton_points": 10},
    "work": {"candidates_measured": 50, "nodes_settled": 1000}}))
"""


def compare(tmp_path, names):
    fake = tmp_path / "skelseg"
    fake.write_text(FAKE_SKELSEG)
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    inputs = []
    for name in names:
        (tmp_path / name).write_text("OFF\n")
        inputs.append(str(tmp_path / name))
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, str(SCRIPT), *inputs, "--skelseg", str(fake),
                          "--out", str(out)], capture_output=True, text=True)
    return run, {pathlib.Path(r["input"]).name: r
                 for r in json.loads((out / "compare.json").read_text())}


def test_refused_by_both_is_the_same_answer(tmp_path):
    run, rows = compare(tmp_path, ["flat.off", "good.off"])
    assert run.returncode == 0, run.stderr
    assert rows["flat.off"]["refused_by_both"] and rows["flat.off"]["identical"]
    assert rows["good.off"]["identical"]
    assert "| flat.off | 192 | refused by both: band exit 2: " in run.stdout
    assert "1 of 1 byte-identical in all three files, 1 in cuts and labels; 1 refused by both; 0 " \
           in run.stdout


def test_failing_one_way_only_is_a_difference(tmp_path):
    run, rows = compare(tmp_path, ["odd.off", "good.off"])
    assert run.returncode == 1
    assert not rows["odd.off"]["identical"]
    assert list(rows["odd.off"]["failed"]) == ["band"]
    assert "| odd.off | 192 | FAILED: band exit 2: skelseg: error: " in run.stdout
    assert "; 1 outside RI error 0.005, with other part counts or failing one way only" in run.stdout
