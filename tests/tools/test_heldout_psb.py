"""bench/heldout_psb.py: the benchmark models the shared subset lacks, laid out for the bench scripts."""
import gzip
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))
import heldout_psb  # noqa: E402

TETRAHEDRON = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"


def make_benchmark(root, segs):
    """A benchmark copy in Princeton's layout: segs maps model -> list of label lists."""
    data = root / "MeshsegBenchmark-1.0" / "data"
    (data / "off").mkdir(parents=True)
    for model, humans in segs.items():
        (data / "off" / f"{model}.off").write_text(TETRAHEDRON)
        folder = data / "seg" / "Benchmark" / str(model)
        folder.mkdir(parents=True)
        for k, labels in enumerate(humans):
            (folder / f"{model}_{k}.seg").write_text("".join(f"{x}\n" for x in labels))
    return root / "MeshsegBenchmark-1.0"


def test_models_outside_the_shared_subset_are_laid_out_with_their_categories(tmp_path):
    benchmark = make_benchmark(tmp_path, {
        1: [[0, 0, 1, 1]],             # in the shared subset: left out
        4: [[0, 1, 1, 2], [0, 0, 0, 1]],
        384: [[1, 1, 2, 2]],
        5: [[0, 1, 2]],                # three labels for four faces: left out
        270: [[0, 0, 0, 0]],           # models 261-280 belong to no category
    })
    shared = tmp_path / "shared"
    (shared / "psb" / "off").mkdir(parents=True)
    (shared / "psb" / "off" / "1.off").write_text(TETRAHEDRON)
    lines = []
    written = heldout_psb.lay_out(benchmark, tmp_path / "out", shared, log=lines.append)
    assert written == [4, 384]
    psb = tmp_path / "out" / "psb"
    assert (psb / "CATEGORIES.tsv").read_text() == "4\tHuman\n384\tFourLeg\n"
    assert sorted(p.name for p in (psb / "off").iterdir()) == ["384.off", "4.off"]
    assert (psb / "off" / "4.off").read_text() == TETRAHEDRON
    with gzip.open(psb / "seg" / "4" / "4_1.seg.gz", "rt") as f:
        assert f.read() == "0\n0\n0\n1\n"
    assert sorted(p.name for p in (psb / "seg" / "4").iterdir()) == ["4_0.seg.gz", "4_1.seg.gz"]
    assert any("5_0.seg: 3 labels for 4 faces" in line for line in lines)
    assert any("model 270 has no benchmark category" in line for line in lines)
    assert not (psb / "seg" / "1").exists() and not (psb / "seg" / "5").exists()


def test_the_category_follows_the_benchmark_numbering():
    assert heldout_psb.category_of(20) == "Human"
    assert heldout_psb.category_of(21) == "Cup"
    assert heldout_psb.category_of(260) == "Bird"
    assert heldout_psb.category_of(261) is None
    assert heldout_psb.category_of(281) == "Armadillo"
    assert heldout_psb.category_of(400) == "FourLeg"
    assert heldout_psb.category_of(401) is None


def test_a_mesh_that_is_not_off_is_left_out_with_its_reason(tmp_path):
    benchmark = make_benchmark(tmp_path, {6: [[0, 0, 0, 0]], 7: [[0, 0, 0, 0]]})
    (benchmark / "data" / "off" / "6.off").write_text("ply\nformat ascii 1.0\n")
    lines = []
    written = heldout_psb.lay_out(benchmark, tmp_path / "out", tmp_path / "none", log=lines.append)
    assert written == [7]
    assert lines == [f"{benchmark / 'data' / 'off' / '6.off'}: does not start with OFF, left out"]


def test_a_folder_without_the_benchmark_and_an_output_in_the_repository_exit_2(tmp_path, capsys):
    assert heldout_psb.main(["--benchmark", str(tmp_path), "--out", str(tmp_path / "out")]) == 2
    assert "no data/off folder" in capsys.readouterr().err
    benchmark = make_benchmark(tmp_path, {4: [[0, 0, 0, 0]]})
    assert heldout_psb.main(["--benchmark", str(benchmark), "--out", str(ROOT / "out" / "x")]) == 2
    assert "inside the repository" in capsys.readouterr().err
    assert not (ROOT / "out" / "x").exists()


@pytest.mark.parametrize("text", ["OFF\n", "OFF\n4 four 0\n"])
def test_an_off_header_without_counts_is_an_error(tmp_path, text):
    path = tmp_path / "m.off"
    path.write_text(text)
    with pytest.raises(ValueError):
        heldout_psb.off_face_count(path)
