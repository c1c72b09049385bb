"""Every script in tools/, bench/ and profiles/ parses its arguments.

`--help` must print a usage text, exit 0 and write nothing (once
`tools/make-fuzz-corpus.py --help` created a folder named `--help`), and an
unknown option must fail with a one-line error before the script does any
work (Python scripts use argparse, which may print its usage line first). Each script runs in an empty temporary working directory; the test
also checks that the repository's `git status` is the same before and after.

Run with: /usr/bin/python3 -m pytest tests/tools/test_tool_arguments.py
"""
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = sorted(
    str(path.relative_to(REPO))
    for pattern in ("tools/*.sh", "tools/*.py", "bench/*.py", "profiles/*.sh", "profiles/*.py")
    for path in REPO.glob(pattern)
)
# Placeholders for required positional arguments, so that argparse reaches
# the unknown option (it reports missing positionals first).
POSITIONALS = {
    "bench/alternate_stages.py": ["skelseg"],
    "bench/compare_search.py": ["mesh.off"],
    "bench/cut_separation.py": ["out"],
    "bench/fit_budget_calibration.py": ["out"],
    "bench/heldout_poses.py": ["--repo", "repo", "--out", "out"],
    "bench/heldout_psb.py": ["--benchmark", "benchmark", "--out", "out"],
    "bench/joint_candidates.py": ["out"],
    "bench/merge_measures.py": ["out"],
    "bench/resolution_consensus.py": ["--data", "data", "--workdir", "work"],
    "bench/trace_handles.py": ["out"],
    "bench/scaling.py": ["mesh.off"],
    "bench/time_budget.py": ["mesh.off"],
    "profiles/stage_table.py": ["report.json"],
    "tools/run-gtest-shards.py": ["test_kernels"],
    "tools/slice_png.py": ["labels.nrrd", "slice.png"],
}


def repository_status():
    return subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=all"],
                          capture_output=True, text=True, check=True).stdout


def run(script, *arguments, cwd):
    path = REPO / script
    command = (["bash", str(path)] if script.endswith(".sh") else ["/usr/bin/python3", str(path)])
    return subprocess.run(command + list(arguments), cwd=cwd, capture_output=True, text=True,
                          timeout=60, env={**os.environ, "SKELSEG_FUZZ_SECONDS": "0"})


def test_every_script_is_covered():
    assert "tools/make-fuzz-corpus.py" in SCRIPTS
    assert "tools/test.sh" in SCRIPTS
    assert len(SCRIPTS) >= 15


@pytest.mark.parametrize("script", SCRIPTS)
def test_help_prints_usage_and_writes_nothing(script, tmp_path):
    before = repository_status()
    result = run(script, "--help", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "usage" in result.stdout.lower(), result.stdout
    assert list(tmp_path.iterdir()) == []
    assert repository_status() == before


@pytest.mark.parametrize("script", SCRIPTS)
def test_unknown_option_fails_with_one_line(script, tmp_path):
    before = repository_status()
    result = run(script, *POSITIONALS.get(script, []), "--no-such-option", cwd=tmp_path)
    assert result.returncode != 0
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    # One error line, after argparse's usage block (which may wrap) if any.
    assert len(lines) == 1 or lines[0].startswith("usage:"), result.stderr
    assert "no-such-option" in lines[-1], result.stderr
    assert list(tmp_path.iterdir()) == []
    assert repository_status() == before
