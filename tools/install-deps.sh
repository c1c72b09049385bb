#!/usr/bin/env bash
# Installs skelseg's build and test dependencies from Debian's packages.
# Idempotent and quick when everything is already there.
set -euo pipefail
usage="usage: tools/install-deps.sh   (installs the missing Debian packages; takes no arguments)"
case "${1:-}" in
  -h|--help) echo "$usage"; exit 0 ;;
  "") ;;
  *) echo "install-deps: unknown argument '$1' ($usage)" >&2; exit 2 ;;
esac
packages=(
  build-essential cmake ninja-build pkg-config
  libtbb-dev libopenvdb-dev libboost-iostreams-dev zlib1g-dev libbz2-dev libeigen3-dev
  libgtest-dev libbenchmark-dev libbenchmark-tools
  libcli11-dev nlohmann-json3-dev libfmt-dev libstb-dev libtinygltf-dev libmeshoptimizer-dev
  clang libclang-rt-14-dev clang-format
  python3-numpy python3-scipy python3-matplotlib python3-pil python3-pytest
  pybind11-dev python3-dev python3-dask python3-distributed
  chromium
  slurm-wlm munge  # tests/cluster: a one-node Slurm for the job-array test
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
