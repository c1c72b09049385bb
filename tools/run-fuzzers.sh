#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/Fuzz*.cpp) with clang and runs each
# for a bounded time. Exits non-zero if any target reports a crash, a leak, a
# sanitizer error, a timeout or an out-of-memory; prints the number of
# executions per target.
#
#   tools/run-fuzzers.sh [SECONDS] [TARGET...]
#
# SECONDS: time per target (default 60). TARGET: e.g. FuzzNrrd (default: all).
# Environment: BUILD_DIR (default build-fuzz), JOBS (ninja -j, default 1),
# CXX (default clang++), FUZZ_ARGS (extra libFuzzer flags, e.g. "-jobs=4").
# New inputs go to BUILD_DIR/fuzz-corpus/<format>/ (the committed seeds in
# tests/fuzz/corpus/ are only read); findings to BUILD_DIR/fuzz-artifacts/.
# See docs/robustness.md for longer runs and how to reproduce a finding.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECONDS_PER_TARGET="${1:-60}"
shift || true
BUILD_DIR="${BUILD_DIR:-$ROOT/build-fuzz}"
JOBS="${JOBS:-1}"
ALL_TARGETS=(FuzzNrrd FuzzBinvox FuzzVdb FuzzOff FuzzObj FuzzStl FuzzPly FuzzSeg)
if [[ $# -gt 0 ]]; then TARGETS=("$@"); else TARGETS=("${ALL_TARGETS[@]}"); fi

if ! [[ "$SECONDS_PER_TARGET" =~ ^[0-9]+$ ]] || [[ "$SECONDS_PER_TARGET" -lt 1 ]]; then
  echo "run-fuzzers: SECONDS must be a positive integer, got '$SECONDS_PER_TARGET'" >&2
  exit 2
fi

# --- build ----------------------------------------------------------------------
if [[ ! -f "$BUILD_DIR/build.ninja" ]]; then
  CXX="${CXX:-clang++}" cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja -DSKELSEG_BUILD_FUZZ=ON \
    -DSKELSEG_BUILD_TESTS=OFF -DSKELSEG_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
ninja -C "$BUILD_DIR" -j "$JOBS" "${TARGETS[@]}"

# --- run ------------------------------------------------------------------------
# Leaks are findings; UBSan errors are fatal (-fno-sanitize-recover=all) and
# print a stack.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:suppressions=$ROOT/tests/ubsan.supp}"
# One known leak inside OpenVDB on truncated files (see the file).
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$ROOT/tests/lsan.supp:print_suppressions=0}"

declare -A RUNS STATUS
failed=0
for target in "${TARGETS[@]}"; do
  format="$(echo "${target#Fuzz}" | tr '[:upper:]' '[:lower:]')"
  seeds="$ROOT/tests/fuzz/corpus/$format"
  work="$BUILD_DIR/fuzz-corpus/$format"
  artifacts="$BUILD_DIR/fuzz-artifacts/$target"
  log="$BUILD_DIR/fuzz-logs/$target.log"
  mkdir -p "$work" "$artifacts" "$(dirname "$log")"
  echo "== $target: ${SECONDS_PER_TARGET} s (seeds $seeds, log $log)"
  set +e
  # shellcheck disable=SC2086
  "$BUILD_DIR/$target" -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -timeout=25 -print_final_stats=1 -artifact_prefix="$artifacts/" ${FUZZ_ARGS:-} \
    "$work" "$seeds" >"$log" 2>&1
  code=$?
  set -e
  runs="$(grep -Eo 'Done [0-9]+ runs' "$log" | tail -1 | grep -Eo '[0-9]+' || true)"
  RUNS[$target]="${runs:-?}"
  if [[ $code -ne 0 ]] || grep -Eq 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|SUMMARY: ' "$log"; then
    STATUS[$target]="FAILED (exit $code)"
    failed=1
    grep -E 'ERROR:|runtime error:|SUMMARY:|Test unit written|uncaught exception' "$log" | head -20 >&2 || true
  else
    STATUS[$target]="ok"
  fi
  echo "   ${STATUS[$target]}, ${RUNS[$target]} executions"
done

echo
printf '%-12s %14s  %s\n' target executions status
for target in "${TARGETS[@]}"; do
  printf '%-12s %14s  %s\n' "$target" "${RUNS[$target]}" "${STATUS[$target]}"
done
if [[ $failed -ne 0 ]]; then
  echo "run-fuzzers: findings above; reproduce with: $BUILD_DIR/<target> <artifact file>" >&2
  exit 1
fi
