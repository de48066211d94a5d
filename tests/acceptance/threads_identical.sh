#!/usr/bin/env bash
# Determinism across thread counts (issue 21): the same scenario and seed run
# with each given --threads must write the same bytes to every output that is
# a function of scenario and seed.
#
# Usage: threads_identical.sh PAVILION SCENARIO DURATION_S WORK_DIR THREADS...
set -euo pipefail
binary=$1
scenario=$2
duration=$3
work=$4
shift 4
files=(events.jsonl trajectories.csv localization.csv metrics.json report.html)
first=""
for threads in "$@"; do
  out="$work/threads_$threads"
  rm -rf "$out"
  "$binary" run "$scenario" --out "$out" --duration "$duration" --threads "$threads" > /dev/null 2>&1 ||
    [ $? -eq 3 ] || { echo "threads_identical.sh: the run with --threads $threads failed" >&2; exit 1; }
  if [ -z "$first" ]; then
    first=$threads
    continue
  fi
  for f in "${files[@]}"; do
    if ! cmp -s "$work/threads_$first/$f" "$out/$f"; then
      echo "threads_identical.sh: $f differs between --threads $first and --threads $threads" >&2
      exit 1
    fi
  done
done
echo "identical for --threads $* (${files[*]})"
