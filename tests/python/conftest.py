"""Fixtures for the Python module's tests: the CLI, generated shapes, NRRD.

The module under test is the one on PYTHONPATH (ctest points it at its
build tree's python/ folder), else build/python; the CLI is SKELSEG_BINARY
(ctest sets it) or build/skelseg. Shapes are generated with `skelseg generate`, once per
session, into a temporary directory.
"""
import gzip
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

# Run by hand without PYTHONPATH: test the build tree's module, not an
# installed copy that may be older (Dask's worker processes inherit the path).
if not os.environ.get("PYTHONPATH") and (REPO / "build" / "python" / "skelseg").is_dir():
    sys.path.insert(0, str(REPO / "build" / "python"))
    os.environ["PYTHONPATH"] = str(REPO / "build" / "python")


def cli_binary() -> pathlib.Path:
    return pathlib.Path(os.environ.get("SKELSEG_BINARY", REPO / "build" / "skelseg"))


def shared_data() -> pathlib.Path:
    return pathlib.Path(os.environ.get("SKELSEG_SHARED_DATA_DIR", REPO.parent / "shared" / "data"))


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(cli_binary()), *map(str, args)], check=True, capture_output=True,
                          text=True)


def read_nrrd(path: pathlib.Path) -> tuple:
    """(header fields, raw data bytes) of an NRRD file as skelseg writes it."""
    blob = path.read_bytes()
    end = blob.index(b"\n\n")
    fields = {}
    for line in blob[:end].decode().splitlines()[1:]:
        if line.startswith("#") or ":" not in line:
            continue
        key, value = line.split(":", 1)
        fields[key.strip()] = value.strip().lstrip("=").strip()
    data = blob[end + 2:]
    if fields.get("encoding") in ("gzip", "gz"):
        data = gzip.decompress(data)
    return fields, data


class Shapes:
    """Generated shapes as .nrrd files, and the CLI's results for them."""

    def __init__(self, directory: pathlib.Path):
        self.directory = directory

    def nrrd(self, name: str, size: int, pose: int = 0) -> pathlib.Path:
        path = self.directory / f"{name}-{size}-{pose}.nrrd"
        if not path.exists():
            run_cli("generate", name, "-o", path, "--size", size, "--pose", pose)
        return path

    def cli_output(self, name: str, size: int, pose: int = 0, *extra: str) -> pathlib.Path:
        outdir = self.directory / f"{name}-{size}-{pose}{''.join(extra)}-out"
        if not (outdir / "labels.nrrd").exists():
            run_cli("segment", self.nrrd(name, size, pose), "-o", outdir, "-q", "--no-preview",
                    "--force", *extra)
        return outdir


@pytest.fixture(scope="session")
def shapes(tmp_path_factory) -> Shapes:
    if not cli_binary().exists():
        pytest.skip(f"no skelseg binary at {cli_binary()}")
    return Shapes(tmp_path_factory.mktemp("shapes"))


@pytest.fixture(scope="session")
def figure_mask(shapes) -> np.ndarray:
    """A small figure (six parts) as read_volume gives it: (nx, ny, nz), Fortran order."""
    import skelseg
    return skelseg.read_volume(shapes.nrrd("figure", 96, 1))
