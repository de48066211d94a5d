#!/usr/bin/env bash
# A long acceptance run of issue 21 through `pavilion sweep` (it resumes: rerun
# `make acceptance` after an interruption and finished runs are kept), then
# judged: every run must have passed every expectation of its scenario.
#
# Usage: sweep_passes.sh PAVILION OUT_DIR SCENARIO [sweep options: --seeds, --duration ...]
set -euo pipefail
binary=$1
out=$2
scenario=$3
shift 3
"$binary" sweep "$scenario" --out "$out" --jobs 1 "$@"
status=0
runs=0
for result in "$out"/runs/*/expectations.json; do
  [ -e "$result" ] || continue
  runs=$((runs + 1))
  run=$(basename "$(dirname "$result")")
  if grep -q '"passed": *true' "$result"; then
    echo "pass  $run"
  else
    echo "FAIL  $run: $(grep -o '"failures": *[0-9]*' "$result")"
    awk -F'"' '/"name":/ { name = $4 } /"status": *"(fail|missing)/ { print "      " $4 ": " name }' "$result"
    status=1
  fi
done
if [ "$runs" -eq 0 ]; then
  echo "sweep_passes.sh: no run of $scenario finished in $out" >&2
  exit 1
fi
echo "summary: $out/sweep.html"
exit $status
