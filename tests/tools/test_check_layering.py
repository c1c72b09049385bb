"""tools/check-layering.py: passes on the real tree, fails on each kind of offence."""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "check-layering.py"


def run(root: pathlib.Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), "--root", str(root)], capture_output=True, text=True)


def make_repo(tmp_path: pathlib.Path, files: dict[str, str]) -> pathlib.Path:
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    subprocess.run(["git", "-C", str(tmp_path), "add", "-A"], check=True)
    return tmp_path


CLEAN = {
    "kernels/base/Error.h": "#pragma once\n#include <string>\n",
    "kernels/Kernel.h": '#include "kernels/base/Error.h"\n',
    "io/Reader.h": '#include "kernels/Kernel.h"\n#include "kernels/base/Error.h"\n',
    "engine/Command.cpp": '#include "io/Reader.h"\n#include "kernels/Kernel.h"\n',
}


def test_real_tree_passes():
    result = run(ROOT)
    assert result.returncode == 0, result.stdout
    assert "0 offences" in result.stdout


def test_clean_layers_pass(tmp_path):
    result = run(make_repo(tmp_path, CLEAN))
    assert result.returncode == 0, result.stdout


def test_kernel_including_engine_fails(tmp_path):
    files = dict(CLEAN, **{"kernels/Bad.cpp": '#include "engine/Command.h"\n'})
    result = run(make_repo(tmp_path, files))
    assert result.returncode == 1
    assert "kernels/Bad.cpp:1" in result.stdout


def test_io_including_engine_fails(tmp_path):
    files = dict(CLEAN, **{"io/mesh/Bad.h": '#pragma once\n#include "engine/Command.h"\n'})
    result = run(make_repo(tmp_path, files))
    assert result.returncode == 1
    assert "io/mesh/Bad.h:2" in result.stdout


def test_base_including_kernels_fails(tmp_path):
    files = dict(CLEAN, **{"kernels/base/Bad.h": '#include "kernels/Kernel.h"\n'})
    result = run(make_repo(tmp_path, files))
    assert result.returncode == 1
    assert "kernels/base/Bad.h:1" in result.stdout


def test_path_beginning_with_dash_fails(tmp_path):
    files = dict(CLEAN, **{"--help/corpus/seed.off": "OFF\n"})
    result = run(make_repo(tmp_path, files))
    assert result.returncode == 1
    assert "--help/corpus/seed.off" in result.stdout
