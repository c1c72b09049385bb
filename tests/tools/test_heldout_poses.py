"""bench/heldout_poses.py: pose frames the shared data lacks, laid out for bench/invariance.py."""
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))
import heldout_poses  # noqa: E402


def frame_text(tag):
    """A one-triangle OBJ whose bytes name the frame."""
    return f"# {tag}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"


def make_copy(root, paths):
    """A work tree of the repository holding models/PATH for each path."""
    for path in paths:
        file = root / "models" / path
        file.parent.mkdir(parents=True, exist_ok=True)
        file.write_text(frame_text(path))
    return root


def third_paths():
    return [path for _, _, path in heldout_poses.SETS["third"]]


def test_every_frame_of_a_set_is_copied_under_its_sequence_name(tmp_path):
    paths = third_paths()
    copy = make_copy(tmp_path / "copy", paths[1:])  # the first frame is missing
    shared = tmp_path / "shared"
    (shared / "poses").mkdir(parents=True)
    # A shared frame: the same bytes as one frame of the set.
    (shared / "poses" / "samba_0000.obj").write_text(frame_text(paths[5]))
    lines = []
    written = heldout_poses.lay_out(heldout_poses.Source(copy), tmp_path / "out", ["third"],
                                    shared, log=lines.append)
    names = written["third"]
    assert len(names) == len(paths) - 2
    assert "elephantgallop_7.obj" not in names  # missing from the copy
    missing = [line for line in lines if "not in the copy" in line]
    assert missing == [f"heldout_poses.py: third: models/{paths[0]} is not in the copy; left out"]
    assert any(f"models/{paths[5]} is a shared frame" in line for line in lines)
    folder = tmp_path / "out" / "third" / "poses"
    assert sorted(p.name for p in folder.iterdir()) == sorted(names)
    for sequence, frame, path in heldout_poses.SETS["third"][1:]:
        target = folder / f"{sequence}_{frame}.obj"
        if path == paths[5]:
            assert not target.exists()
        else:
            assert target.read_text() == frame_text(path)


def test_the_sets_name_distinct_frames_and_every_sequence_has_several():
    for name, frames in heldout_poses.SETS.items():
        assert len({(s, f) for s, f, _ in frames}) == len(frames), name
        assert len({p for _, _, p in frames}) == len(frames), name
        sequences = {}
        for sequence, _, _ in frames:
            sequences[sequence] = sequences.get(sequence, 0) + 1
        assert min(sequences.values()) >= 3, name
    # The traced frames are not read again as untraced or third ones.
    traced = {p for _, _, p in heldout_poses.SETS["traced"]}
    for name in ("untraced", "third", "fourth"):
        assert not traced & {p for _, _, p in heldout_poses.SETS[name]}, name


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_a_bare_clone_is_read_with_git_show(tmp_path):
    paths = third_paths()[:4]
    work = make_copy(tmp_path / "work", paths)
    git = ["git", "-c", "user.name=t", "-c", "user.email=t@t", "-c", "init.defaultBranch=main"]
    subprocess.run(git + ["init", "-q", str(work)], check=True)
    subprocess.run(git + ["-C", str(work), "add", "models"], check=True)
    subprocess.run(git + ["-C", str(work), "commit", "-q", "-m", "frames"], check=True)
    bare = tmp_path / "bare.git"
    subprocess.run(git + ["clone", "-q", "--bare", str(work), str(bare)], check=True)
    source = heldout_poses.Source(bare)
    assert source.usable() and not source.tree
    assert source.read(paths[2]) == frame_text(paths[2]).encode()
    assert source.read("elephant-gallop/999.obj") is None
    written = heldout_poses.lay_out(source, tmp_path / "out", ["third"], tmp_path / "no-shared",
                                    log=lambda line: None)
    assert written["third"] == ["elephantgallop_7.obj", "elephantgallop_19.obj",
                                "elephantgallop_31.obj", "elephantgallop_43.obj"]


def test_a_copy_without_models_and_an_output_in_the_repository_are_refused(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    assert heldout_poses.main(["--repo", str(tmp_path / "empty"), "--out",
                               str(tmp_path / "out")]) == 2
    assert "no models/ folder" in capsys.readouterr().err
    copy = make_copy(tmp_path / "copy", third_paths()[:1])
    assert heldout_poses.main(["--repo", str(copy), "--out", str(ROOT / "poses-out")]) == 2
    assert "inside the repository" in capsys.readouterr().err
    assert not (ROOT / "poses-out").exists()
    assert heldout_poses.main(["--repo", str(copy), "--out", str(tmp_path / "out"),
                               "--sets", "fifth"]) == 2
    assert "no set 'fifth'" in capsys.readouterr().err
