"""tools/reference-outputs.sh compare: names every output that differs and fails on it."""
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "reference-outputs.sh"


def outputs(root: pathlib.Path, labels: bytes) -> pathlib.Path:
    """Two runs' outputs; the input folder `in` and files outside the list are ignored."""
    for run in ("sphere", "figure1-levels/levels/0"):
        (root / run).mkdir(parents=True, exist_ok=True)
        (root / run / "labels.nrrd").write_bytes(labels)
        (root / run / "cuts.ply").write_bytes(b"ply\n")
    (root / "in").mkdir(exist_ok=True)
    (root / "in" / "labels.nrrd").write_bytes(labels + b"input")
    (root / "sphere" / "preview.png").write_bytes(labels + b"png")
    return root


def compare(a: pathlib.Path, b: pathlib.Path) -> subprocess.CompletedProcess:
    return subprocess.run(["bash", str(SCRIPT), "compare", str(a), str(b)], capture_output=True, text=True)


def test_identical_outputs_pass(tmp_path):
    a = outputs(tmp_path / "a", b"same")
    b = outputs(tmp_path / "b", b"same")
    (b / "in" / "labels.nrrd").write_bytes(b"other input")
    (b / "sphere" / "preview.png").write_bytes(b"other preview")
    run = compare(a, b)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "compared 4 files; identical" in run.stdout


def test_a_changed_label_file_is_named_and_fails(tmp_path):
    a = outputs(tmp_path / "a", b"same")
    b = outputs(tmp_path / "b", b"same")
    (b / "figure1-levels" / "levels" / "0" / "labels.nrrd").write_bytes(b"changed")
    run = compare(a, b)
    assert run.returncode == 1
    assert "DIFFER: ./figure1-levels/levels/0/labels.nrrd" in run.stdout
    assert "DIFFERENT" in run.stdout


def test_a_missing_output_fails(tmp_path):
    a = outputs(tmp_path / "a", b"same")
    b = outputs(tmp_path / "b", b"same")
    (b / "sphere" / "cuts.ply").unlink()
    run = compare(a, b)
    assert run.returncode == 1
    assert "DIFFER: ./sphere/cuts.ply" in run.stdout


def test_wrong_arguments_give_usage_and_exit_2(tmp_path):
    run = subprocess.run(["bash", str(SCRIPT), "compare", str(tmp_path)], capture_output=True, text=True)
    assert run.returncode == 2
    assert "usage:" in run.stderr
