#!/usr/bin/env bash
# The twins lint fails on each kind of twin and passes on a clean tree.
set -u
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/core/types" "$tmp/nav" "$tmp/sim" "$tmp/scenarios"
cat > "$tmp/core/types/pose2.cc" <<'CC'
double NormalizeAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }
CC
echo 'int ok = 0;' > "$tmp/sim/clean.cc"
bash "$here/check_twins.sh" "$tmp" > /dev/null || { echo "selftest: a clean tree failed"; exit 1; }
expect_failure() {  # expect_failure NAME CODE
  printf '%s\n' "$2" > "$tmp/sim/twin.cc"
  if bash "$here/check_twins.sh" "$tmp" > /dev/null; then
    echo "selftest: $1 was not caught"
    exit 1
  fi
  rm "$tmp/sim/twin.cc"
}
expect_failure "a removed type" 'struct SimRobotSetup {};'
expect_failure "a removed type in use" 'const RobotSpec& spec = world.robot_spec(0);'
expect_failure "angle wrapping" 'double Wrap(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }'
expect_failure "ticks to travel" 'const double per_tick = 2.0 * std::numbers::pi / r.ticks_per_revolution;'
expect_failure "a point-segment distance" 'double PointSegmentDistance(const V& p, const V& a, const V& b) {'
echo "twins lint selftest ok"
