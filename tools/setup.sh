#!/usr/bin/env bash
# Set-up command 1: install dependencies, build (Release), install the Python
# module skelseg, and segment the bundled example: a generated articulated
# figure. Results land in out/figure/ (preview.png, labels.nrrd,
# skeleton.ply, cuts.ply, report.json).
set -euo pipefail
usage="usage: tools/setup.sh   (install dependencies, build, segment the example; no arguments)"
case "${1:-}" in
  -h|--help) echo "$usage"; exit 0 ;;
  "") ;;
  *) echo "setup: unknown argument '$1' ($usage)" >&2; exit 2 ;;
esac
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target skelseg
# The Python module (when pybind11 is installed): built, then installed into
# /usr/bin/python3's site-packages so that `python3 -c "import skelseg"` works
# (docs/python.md).
if ninja -C build -t targets all | grep '^skelseg_python:' > /dev/null; then  # not -q: pipefail
  cmake --build build -j"$(nproc)" --target skelseg_python
  SUDO=""
  [ -w "$(sed -n 's/^SKELSEG_PYTHON_INSTALL_DIR:PATH=//p' build/CMakeCache.txt)" ] || SUDO="sudo"
  $SUDO cmake --install build --component python
fi
mkdir -p out
./build/skelseg generate figure -o out/figure.nrrd --size 160 --pose 1
./build/skelseg segment out/figure.nrrd -o out/figure --force
echo "setup: done; open out/figure/preview.png"
