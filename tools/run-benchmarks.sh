#!/usr/bin/env bash
# Runs every benchmark at its smallest size and compares the result with
# bench/baseline.json (bench/README.md). Usage: tools/run-benchmarks.sh [build-dir]
#
# Timings on a shared CI machine are noisy, so a slower run is reported, not
# failed. The script fails when the benchmark executable fails or when a
# benchmark of the baseline no longer exists (renamed or removed: regenerate
# the baseline, see bench/README.md).
set -euo pipefail
usage="usage: tools/run-benchmarks.sh [BUILD_DIR]   (default: build)"
case "${1:-}" in
  -h|--help) echo "$usage"; exit 0 ;;
  -*) echo "run-benchmarks: unknown option '$1' ($usage)" >&2; exit 2 ;;
esac
if [[ $# -gt 1 ]]; then echo "run-benchmarks: too many arguments ($usage)" >&2; exit 2; fi
cd "$(dirname "$0")/.."
build="${1:-build}"
bench="$build/skelseg_bench"
baseline=bench/baseline.json
out="$build/bench-smallest.json"
filter='/64$'
compare=/usr/share/benchmark/compare.py
# compare.py needs scipy; Debian's python3-scipy is for the system python.
python=/usr/bin/python3

if [ ! -x "$bench" ]; then
  echo "run-benchmarks: $bench not found (build the skelseg_bench target)" >&2
  exit 1
fi
"$bench" --benchmark_filter="$filter" --benchmark_out="$out" --benchmark_out_format=json

"$python" - "$baseline" "$out" <<'EOF'
import json, sys
baseline, current = (json.load(open(p))["benchmarks"] for p in sys.argv[1:3])
missing = sorted({b["name"] for b in baseline} - {b["name"] for b in current})
added = sorted({b["name"] for b in current} - {b["name"] for b in baseline})
for name in added:
    print(f"run-benchmarks: new benchmark (not in the baseline): {name}")
if missing:
    for name in missing:
        print(f"run-benchmarks: baseline benchmark missing from this run: {name}", file=sys.stderr)
    sys.exit(1)
EOF

if [ -f "$compare" ] && "$python" -c 'import scipy' 2>/dev/null; then
  "$python" "$compare" --no-color benchmarks "$baseline" "$out"
else
  echo "run-benchmarks: $compare or python3-scipy missing; comparison skipped (results in $out)"
fi

# `skelseg batch` against a loop of `skelseg segment` on eight generated
# shapes (bench/batch_throughput.py --small): shapes per minute beside
# bench/batch_baseline.json. Reported, never failed on timing.
if [ -x "$build/skelseg" ]; then
  "$python" bench/batch_throughput.py --small --skelseg "$build/skelseg" --out "$build/batch-throughput"
else
  echo "run-benchmarks: $build/skelseg not found; batch throughput skipped"
fi
