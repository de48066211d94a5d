#!/usr/bin/env bash
# Compares two pavilion binaries' speed, interleaved back to back (old, new,
# old, new, ...) so that drifts of a shared machine hit both alike:
#   - `pavilion bench hall --robots N --runs 1` CPU real-time factor for N = 10 and 100;
#   - the stepping loop's CPU seconds (performance.json loop_cpu_s) of
#     office_tour and expo_visitors at seed 1.
# Prints each figure's median per binary and the ratio new/old.
# Usage: scripts/bench_compare.sh OLD_BINARY NEW_BINARY [ROUNDS=5]
set -euo pipefail
old=$1
new=$2
rounds=${3:-5}
here=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
figure() {  # figure BINARY KIND -> one number
  local bin=$1 kind=$2
  case $kind in
    hall_*)
      "$bin" bench hall --robots "${kind#hall_}" --runs 1 --threads 2 --json "$work/b.json" > /dev/null 2>&1
      python3 -c "import json;print(json.load(open('$work/b.json'))['median']['cpu_real_time_factor'])" ;;
    *)
      rm -rf "$work/run"
      "$bin" run "$here/scenarios/$kind.yaml" --out "$work/run" --seed 1 --threads 2 > /dev/null 2>&1
      python3 -c "import json;print(json.load(open('$work/run/performance.json'))['loop_cpu_s'])" ;;
  esac
}
for kind in hall_10 hall_100 office_tour expo_visitors; do
  : > "$work/$kind.old"; : > "$work/$kind.new"
  for _ in $(seq "$rounds"); do
    figure "$old" "$kind" >> "$work/$kind.old"
    figure "$new" "$kind" >> "$work/$kind.new"
  done
  python3 - "$kind" "$work/$kind.old" "$work/$kind.new" <<'PY'
import statistics, sys
kind, a, b = sys.argv[1], [float(x) for x in open(sys.argv[2])], [float(x) for x in open(sys.argv[3])]
unit = "CPU RTF (x)" if kind.startswith("hall") else "loop CPU s"
ma, mb = statistics.median(a), statistics.median(b)
print(f"{kind:14s} {unit:12s} old {ma:9.3f}  new {mb:9.3f}  new/old {mb / ma:6.3f}   "
      f"old runs {' '.join(f'{x:.3f}' for x in a)} | new runs {' '.join(f'{x:.3f}' for x in b)}")
PY
done
rm -rf "$work"
