#!/usr/bin/env bash
# Set-up command 2 (and what CI runs): check the include layering and the
# formatting, build everything in Release with strict warnings and run the
# test suites, fastest first, slow ones last:
#   bench  every benchmark at its smallest size, compared with the baseline
#   unit   kernels, readers/writers, scoring          (label unit; run in shards,
#          tools/run-gtest-shards.py)
#   scene  generated shapes end to end                (label scene)
#   python the Python module with pytest, Dask included (label python)
#   browser viewer.html in headless Chromium           (label browser)
#   asan   unit tests under AddressSanitizer + UBSan, built with clang (SKELSEG_CI_ASAN=0 skips)
#   fuzz   each parser under libFuzzer for a bounded time, JOBS targets at a time
#          (SKELSEG_FUZZ_SECONDS per target, default 20; 0 skips)
#   cluster  `skelseg batch` as a Slurm job array on a one-node Slurm it starts
#          (label cluster; skipped without slurm-wlm/munge or root)
#   slow   robustness on real data and degenerate shapes (label slow)
# The benchmarks run right after the build, on an otherwise idle machine (they
# compare speed with the baseline). The fuzz targets are then built in the
# background (one job) while the Release suites run, which leave part of the
# cores idle; its log is build-ci/fuzz-build.log. The sanitizer build starts in
# the background after the scene tests, beside the suites that mostly wait
# (Python, browser, the tools' tests, Slurm); its log is
# build-ci/asan-build.log. The scene and slow tests run two at a time (each in
# its own temporary directory; none is timed, and two overlap the serial parts
# of each other's runs).
set -euo pipefail
usage="usage: tools/test.sh   (build and run every suite as CI does; settings via SKELSEG_* variables)"
case "${1:-}" in
  -h|--help) echo "$usage"; exit 0 ;;
  "") ;;
  *) echo "test: unknown argument '$1' ($usage)" >&2; exit 2 ;;
esac
cd "$(dirname "$0")/.."
tools/install-deps.sh
jobs="${SKELSEG_JOBS:-2}"
fuzz_seconds="${SKELSEG_FUZZ_SECONDS:-20}"
start=$(date +%s)
stamp() { echo "== $1 ($(( $(date +%s) - start )) s)"; }

stamp "layering and format checks"
/usr/bin/python3 tools/check-layering.py
tools/check-format.sh

stamp "build (Release, strict warnings)"
cmake -S . -B build-ci -G Ninja -DCMAKE_BUILD_TYPE=Release -DSKELSEG_WERROR=ON > /dev/null
cmake --build build-ci -j"$jobs"

stamp "benchmarks (smallest size) vs baseline"
tools/run-benchmarks.sh build-ci

# Builds in the background run in their own process groups, so that a failing
# suite below, which ends this script, stops each whole build (ninja and its
# compilers) with it.
background_builds=()
trap 'for group in "${background_builds[@]}"; do kill -- "-$group" 2>/dev/null || true; done' EXIT
start_background() {  # start_background LOG COMMAND...: pid in $started
  local log="$1"; shift
  setsid "$@" > "$log" 2>&1 &
  started=$!
  background_builds+=("$started")
}
finish_background() {  # finish_background PID LOG WHAT
  if ! wait "$1"; then
    cat "$2"
    echo "test.sh: $3 failed" >&2
    exit 1
  fi
}

fuzz_build=""
if [ "$fuzz_seconds" != "0" ]; then
  stamp "fuzz build started in the background"
  start_background build-ci/fuzz-build.log env JOBS=1 tools/run-fuzzers.sh --build-only
  fuzz_build=$started
fi

stamp "unit tests"
# The label's test executables in a few shards of one process each (a process
# per test spent more time starting than some tests run).
/usr/bin/python3 tools/run-gtest-shards.py --jobs "$jobs" --log-dir build-ci/unit-shard-logs \
  build-ci/test_engine build-ci/test_io build-ci/test_kernels
stamp "scene tests"
ctest --test-dir build-ci -L scene --output-on-failure -j"$jobs"

asan_build=""
if [ "${SKELSEG_CI_ASAN:-1}" != "0" ]; then
  stamp "sanitizer build (ASan+UBSan, clang) started in the background"
  start_background build-ci/asan-build.log env CXX=clang++ JOBS="$jobs" tools/run-asan-tests.sh --build-only
  asan_build=$started
fi
stamp "tools' tests"
ctest --test-dir build-ci -L unit -R '^tools_pytest$' --output-on-failure
stamp "python tests"
ctest --test-dir build-ci -L python --output-on-failure
stamp "browser tests"
ctest --test-dir build-ci -L browser --output-on-failure
stamp "cluster tests (a one-node Slurm)"
ctest --test-dir build-ci -L cluster --output-on-failure

if [ -n "$fuzz_build" ]; then
  stamp "waiting for the fuzz build"
  finish_background "$fuzz_build" build-ci/fuzz-build.log "fuzz build"
fi
if [ -n "$asan_build" ]; then
  stamp "waiting for the sanitizer build"
  finish_background "$asan_build" build-ci/asan-build.log "sanitizer build"
  stamp "unit tests under ASan+UBSan"
  JOBS="$jobs" tools/run-asan-tests.sh
fi
if [ "$fuzz_seconds" != "0" ]; then
  stamp "fuzzing"
  JOBS="$jobs" tools/run-fuzzers.sh "$fuzz_seconds"
fi

stamp "slow tests"
ctest --test-dir build-ci -L slow --output-on-failure -j"$jobs"
stamp "all passed"
