#!/usr/bin/env bash
# Set-up command 2 (and what CI runs): build everything in Release with strict
# warnings and run the test suites, fastest first, slow ones last:
#   unit   kernels, readers/writers, scoring          (label unit)
#   scene  generated shapes end to end                (label scene)
#   bench  every benchmark at its smallest size, compared with the baseline
#   asan   unit tests under AddressSanitizer + UBSan   (SKELSEG_CI_ASAN=0 skips)
#   fuzz   each parser under libFuzzer for a bounded time (SKELSEG_FUZZ_SECONDS, default 30; 0 skips)
#   slow   robustness on real data and degenerate shapes (label slow)
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
jobs="${SKELSEG_JOBS:-2}"
start=$(date +%s)
stamp() { echo "== $1 ($(( $(date +%s) - start )) s)"; }

stamp "build (Release, strict warnings)"
cmake -S . -B build-ci -G Ninja -DCMAKE_BUILD_TYPE=Release -DSKELSEG_WERROR=ON > /dev/null
cmake --build build-ci -j"$jobs"

stamp "unit tests"
ctest --test-dir build-ci -L unit --output-on-failure -j"$jobs"
stamp "scene tests"
ctest --test-dir build-ci -L scene --output-on-failure

stamp "benchmarks (smallest size) vs baseline"
tools/run-benchmarks.sh build-ci

if [ "${SKELSEG_CI_ASAN:-1}" != "0" ]; then
  stamp "unit tests under ASan+UBSan"
  JOBS="$jobs" tools/run-asan-tests.sh
fi
if [ "${SKELSEG_FUZZ_SECONDS:-30}" != "0" ]; then
  stamp "fuzzing"
  JOBS="$jobs" tools/run-fuzzers.sh "${SKELSEG_FUZZ_SECONDS:-30}"
fi

stamp "slow tests"
ctest --test-dir build-ci -L slow --output-on-failure
stamp "all passed"
