#!/usr/bin/env bash
# Set-up command 1: install dependencies, build (Release), and segment the
# bundled example: a generated articulated figure. Results land in
# out/figure/ (preview.png, labels.nrrd, skeleton.ply, cuts.ply, report.json).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target skelseg
mkdir -p out
./build/skelseg generate figure -o out/figure.nrrd --size 160 --pose 1
./build/skelseg segment out/figure.nrrd -o out/figure --force
echo "setup: done; open out/figure/preview.png"
