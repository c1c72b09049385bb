#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/Fuzz*.cpp) with clang and runs each
# for a bounded time. Exits non-zero if any target reports a crash, a leak, a
# sanitizer error, a timeout or an out-of-memory; prints the number of
# executions per target.
#
#   tools/run-fuzzers.sh [SECONDS] [TARGET...]
#   tools/run-fuzzers.sh --build-only [TARGET...]
#
# SECONDS: time per target (default 60). TARGET: e.g. FuzzNrrd (default: all).
# --build-only: configure and build the targets, run nothing (CI builds them
# while the sanitizer build runs, tools/test.sh).
# Environment: BUILD_DIR (default build-fuzz), JOBS (ninja -j, default 1),
# PARALLEL (targets fuzzed at the same time, each a single process; default
# JOBS), CXX (default clang++), FUZZ_ARGS (extra libFuzzer flags, e.g.
# "-jobs=4").
# New inputs go to BUILD_DIR/fuzz-corpus/<format>/ (the committed seeds in
# tests/fuzz/corpus/ are only read); findings to BUILD_DIR/fuzz-artifacts/.
# See docs/robustness.md for longer runs and how to reproduce a finding.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_ONLY=0
usage="usage: tools/run-fuzzers.sh [SECONDS] [TARGET...] | --build-only [TARGET...]"
case "${1:-}" in
  -h|--help) echo "$usage"; exit 0 ;;
  --build-only) ;;
  -*) echo "run-fuzzers: unknown option '$1' ($usage)" >&2; exit 2 ;;
esac
if [[ "${1:-}" == "--build-only" ]]; then
  BUILD_ONLY=1
  shift
  SECONDS_PER_TARGET=1
else
  SECONDS_PER_TARGET="${1:-60}"
  shift || true
fi
BUILD_DIR="${BUILD_DIR:-$ROOT/build-fuzz}"
JOBS="${JOBS:-1}"
PARALLEL="${PARALLEL:-$JOBS}"
ALL_TARGETS=(FuzzNrrd FuzzBinvox FuzzVdb FuzzOff FuzzObj FuzzStl FuzzPly FuzzSeg)
if [[ $# -gt 0 ]]; then TARGETS=("$@"); else TARGETS=("${ALL_TARGETS[@]}"); fi
for target in "${TARGETS[@]}"; do
  if [[ " ${ALL_TARGETS[*]} " != *" $target "* ]]; then
    echo "run-fuzzers: unknown target '$target' (known: ${ALL_TARGETS[*]})" >&2
    exit 2
  fi
done

if ! [[ "$SECONDS_PER_TARGET" =~ ^[0-9]+$ ]] || [[ "$SECONDS_PER_TARGET" -lt 1 ]]; then
  echo "run-fuzzers: SECONDS must be a positive integer, got '$SECONDS_PER_TARGET'" >&2
  exit 2
fi
if ! [[ "$PARALLEL" =~ ^[0-9]+$ ]] || [[ "$PARALLEL" -lt 1 ]]; then
  echo "run-fuzzers: PARALLEL must be a positive integer, got '$PARALLEL'" >&2
  exit 2
fi

# --- build ----------------------------------------------------------------------
if [[ ! -f "$BUILD_DIR/build.ninja" ]]; then
  CXX="${CXX:-clang++}" cmake -S "$ROOT" -B "$BUILD_DIR" -G Ninja -DSKELSEG_BUILD_FUZZ=ON \
    -DSKELSEG_BUILD_TESTS=OFF -DSKELSEG_BUILD_BENCH=OFF -DSKELSEG_BUILD_PYTHON=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
ninja -C "$BUILD_DIR" -j "$JOBS" "${TARGETS[@]}"
[[ $BUILD_ONLY -eq 1 ]] && exit 0

# --- run ------------------------------------------------------------------------
# Leaks are findings; UBSan errors are fatal (-fno-sanitize-recover=all) and
# print a stack.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:suppressions=$ROOT/tests/ubsan.supp}"
# One known leak inside OpenVDB on truncated files (see the file).
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$ROOT/tests/lsan.supp:print_suppressions=0}"

# Up to PARALLEL targets run at once, each one libFuzzer process in the
# background writing its own log; its exit code goes to <log>.exit. A target
# is judged when its process has ended.
declare -A RUNS=() STATUS=() PIDS=()   # PIDS: pid -> target, for the targets still running
failed=0
stop_running() {   # the fuzzers still running, then their wrapper subshells
  local pid
  for pid in "${!PIDS[@]}"; do pkill -TERM -P "$pid" 2>/dev/null || true; kill "$pid" 2>/dev/null || true; done
}
trap stop_running EXIT
trap 'stop_running; exit 130' INT TERM

log_of() { echo "$BUILD_DIR/fuzz-logs/$1.log"; }

start_target() {
  local target="$1" format seeds work artifacts log
  format="$(echo "${target#Fuzz}" | tr '[:upper:]' '[:lower:]')"
  seeds="$ROOT/tests/fuzz/corpus/$format"
  work="$BUILD_DIR/fuzz-corpus/$format"
  artifacts="$BUILD_DIR/fuzz-artifacts/$target"
  log="$(log_of "$target")"
  mkdir -p "$work" "$artifacts" "$(dirname "$log")"
  rm -f "$log.exit"
  echo "== $target: ${SECONDS_PER_TARGET} s (seeds $seeds, log $log)"
  (
    set +e
    # shellcheck disable=SC2086
    "$BUILD_DIR/$target" -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=2048 -malloc_limit_mb=1024 \
      -timeout=25 -print_final_stats=1 -artifact_prefix="$artifacts/" ${FUZZ_ARGS:-} \
      "$work" "$seeds" >"$log" 2>&1
    echo $? >"$log.exit"
  ) &
  PIDS[$!]="$target"
}

judge_target() {
  local target="$1" log code runs
  log="$(log_of "$target")"
  code="$(cat "$log.exit" 2>/dev/null || echo '?')"
  runs="$(grep -Eo 'Done [0-9]+ runs' "$log" | tail -1 | grep -Eo '[0-9]+' || true)"
  RUNS[$target]="${runs:-?}"
  if [[ "$code" != 0 ]] || grep -Eq 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|SUMMARY: ' "$log"; then
    STATUS[$target]="FAILED (exit $code)"
    failed=1
    grep -E 'ERROR:|runtime error:|SUMMARY:|Test unit written|uncaught exception' "$log" | head -20 >&2 || true
  else
    STATUS[$target]="ok"
  fi
  echo "   $target: ${STATUS[$target]}, ${RUNS[$target]} executions"
}

# Waits until at least one running target has ended (its subshell writes the
# exit code as its last act; polled once a second) and judges those that have.
reap() {
  local pid ended=0
  while [[ $ended -eq 0 ]]; do
    for pid in "${!PIDS[@]}"; do
      if [[ -f "$(log_of "${PIDS[$pid]}").exit" ]]; then
        wait "$pid" || true
        judge_target "${PIDS[$pid]}"
        unset "PIDS[$pid]"
        ended=1
      fi
    done
    [[ $ended -eq 1 ]] || sleep 1
  done
}

for target in "${TARGETS[@]}"; do
  while [[ ${#PIDS[@]} -ge $PARALLEL ]]; do reap; done
  start_target "$target"
done
while [[ ${#PIDS[@]} -gt 0 ]]; do reap; done

echo
printf '%-12s %14s  %s\n' target executions status
for target in "${TARGETS[@]}"; do
  printf '%-12s %14s  %s\n' "$target" "${RUNS[$target]}" "${STATUS[$target]}"
done
if [[ $failed -ne 0 ]]; then
  echo "run-fuzzers: findings above; reproduce with: $BUILD_DIR/<target> <artifact file>" >&2
  exit 1
fi
