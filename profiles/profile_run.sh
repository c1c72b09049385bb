#!/usr/bin/env bash
# Profiles one reference run: the per-stage breakdown from report.json, and a
# sampling profile of the hot functions with perf (Debian: linux-perf) when
# the machine allows it, else an instruction-count profile with callgrind
# (valgrind) on a smaller resolution.
#
# Usage: profiles/profile_run.sh INPUT RESOLUTION [NAME]
#   e.g. profiles/profile_run.sh ../shared/data/shapes/armadillo.obj 256 armadillo
# Writes profiles/NAME-RESOLUTION.md (stage table + top functions).
set -euo pipefail
usage="usage: profiles/profile_run.sh INPUT RESOLUTION [NAME]"
case "${1:-}" in
  -h|--help) echo "$usage"; exit 0 ;;
  -*) echo "profile_run: unknown option '$1' ($usage)" >&2; exit 2 ;;
esac
if [[ $# -lt 2 || $# -gt 3 ]]; then echo "profile_run: expected 2 or 3 arguments, got $# ($usage)" >&2; exit 2; fi
cd "$(dirname "$0")/.."
input=$1; resolution=$2; name=${3:-$(basename "${input%.*}")}
exe=${SKELSEG:-build/skelseg}
out=$(mktemp -d)
record="profiles/$name-$resolution.md"
{
  echo "# Profile: $name at resolution $resolution"
  echo
  echo "Command: \`$exe segment $input -o OUT --resolution $resolution -q\` on $(nproc) vCPUs, $(date -u +%Y-%m-%d)."
  echo
} > "$record"
if command -v perf >/dev/null && perf stat -e instructions true >/dev/null 2>&1; then
  perf record -g -o "$out/perf.data" "$exe" segment "$input" -o "$out/run" --resolution "$resolution" -q
  /usr/bin/python3 profiles/stage_table.py "$out/run/report.json" >> "$record"
  {
    echo "## Hottest functions (perf, self time)"
    echo
    echo '```'
    perf report -i "$out/perf.data" --no-children --stdio 2>/dev/null | grep -E '^ +[0-9]+\.[0-9]+%' | head -20 | cut -c1-150
    echo '```'
  } >> "$record"
else
  "$exe" segment "$input" -o "$out/run" --resolution "$resolution" -q
  /usr/bin/python3 profiles/stage_table.py "$out/run/report.json" >> "$record"
  small=$(( resolution / 2 ))
  valgrind --tool=callgrind --callgrind-out-file="$out/callgrind.out" "$exe" segment "$input" -o "$out/cg" \
    --resolution "$small" -q --threads 1 --no-preview
  { echo "## Hottest functions (callgrind, instructions, resolution $small)"; echo; echo '```';
    callgrind_annotate "$out/callgrind.out" | head -40; echo '```'; } >> "$record"
fi
rm -rf "$out"
echo "wrote $record"
