#!/usr/bin/env bash
# Peak memory of a long run and its flatness in duration (issue 21, expo_rush):
# the run's peak RSS at DURATION_S and at twice it must stay under MAX_MB and
# within 10 % of each other.
#
# Usage: memory_flat.sh PAVILION SCENARIO DURATION_S MAX_MB WORK_DIR
set -euo pipefail
binary=$1
scenario=$2
duration=$3
max_mb=$4
work=$5
peak() {
  local out="$work/run_$1"
  rm -rf "$out"
  "$binary" run "$scenario" --out "$out" --duration "$1" > "$out.log" 2>&1 || [ $? -eq 3 ]
  grep -o 'peak RSS [0-9]*' "$out.log" | grep -o '[0-9]*$'
}
mkdir -p "$work"
short=$(peak "$duration")
long=$(peak "$(awk "BEGIN{print 2*$duration}")")
echo "peak RSS: $short MB at $duration s, $long MB at twice that (limit $max_mb MB)"
awk -v a="$short" -v b="$long" -v m="$max_mb" 'BEGIN { exit !(b <= m && a <= m && b <= 1.1 * a) }'
