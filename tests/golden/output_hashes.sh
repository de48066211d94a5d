#!/usr/bin/env bash
# Runs every shipped scenario at seed 1 for 60 s with two threads (one process
# per run) and prints the SHA-256 of the outputs that are a function of scenario
# and seed: events.jsonl, trajectories.csv, localization.csv, scans.bin and
# metrics.json. With --check FILE, compares them with FILE (recorded from an
# earlier commit) and exits 1 naming every file that differs.
#
# Usage: output_hashes.sh PAVILION_BINARY SOURCE_DIR [--check HASHES] [--work DIR]
set -euo pipefail
binary=$1
source_dir=$2
shift 2
check=""
work=$(mktemp -d)
while [ $# -gt 0 ]; do
  case $1 in
    --check) check=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) echo "output_hashes.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
mapfile -t scenarios < <(cd "$source_dir" && ls scenarios/*.yaml scenarios/hall_bench/*.yaml scenarios/ci/*.yaml | sort)
actual="$work/hashes.sha256"
: > "$actual"
for s in "${scenarios[@]}"; do
  name=$(basename "$s" .yaml)
  out="$work/$name"
  rm -rf "$out"
  # Exit 3 is a finished run whose expect: block failed: a scenario test cut to 60 s
  # (scenarios/ci/computer2000_short asks for an errand done by 120 s); its outputs count.
  "$binary" run "$source_dir/$s" --out "$out" --seed 1 --duration 60 --threads 2 > /dev/null ||
    [ $? -eq 3 ]
  for f in events.jsonl trajectories.csv localization.csv scans.bin metrics.json; do
    [ -f "$out/$f" ] || continue
    echo "$(sha256sum < "$out/$f" | cut -d' ' -f1)  $name/$f" >> "$actual"
  done
  rm -rf "$out"
done
if [ -z "$check" ]; then
  cat "$actual"
  exit 0
fi
if diff <(grep -v "^#" "$check" | sort -k2) <(sort -k2 "$actual") > "$work/diff"; then
  echo "output hashes: $(wc -l < "$actual") files identical to $(basename "$check")"
  exit 0
fi
echo "output hashes differ from $check (< recorded, > now):"
cat "$work/diff"
exit 1
