#!/usr/bin/env bash
# Confirms that check_layers.sh fails on each kind of layer violation and passes
# on a clean tree, so the lint test cannot pass vacuously.
set -u
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

expect() {  # expect WANT_STATUS FILE CONTENT
  local want=$1 file=$2 content=$3
  rm -rf "$tmp/tree"
  mkdir -p "$tmp/tree/core" "$tmp/tree/nav" "$tmp/tree/sim" "$tmp/tree/scenarios"
  echo '#include "core/types/pose2.h"' > "$tmp/tree/core/ok.h"
  mkdir -p "$(dirname "$tmp/tree/$file")"
  printf '%s\n' "$content" > "$tmp/tree/$file"
  bash "$here/check_layers.sh" "$tmp/tree" > /dev/null
  local got=$?
  if [ "$got" -ne "$want" ]; then
    echo "FAIL: $file with '$content': status $got, wanted $want"
    fail=1
  fi
}

expect 0 core/clean.cc '#include <Eigen/Core>'
expect 1 core/bad.cc '#include "sim/world/world.h"'
expect 1 core/bad.h '#include <yaml-cpp/yaml.h>'
expect 1 core/bad.cc '#include "nav/planner.h"'
expect 1 nav/bad.cc '#include "sim/world/world.h"'
expect 1 nav/bad.h '#include <btBulletDynamicsCommon.h>'
expect 1 sim/bad.h '#include <btBulletDynamicsCommon.h>'
expect 0 sim/fine.cc '#include <btBulletDynamicsCommon.h>'
expect 1 sim/bad.cc '#include "scenarios/config/scenario.h"'
expect 1 sim/bad.h '#  include <assimp/scene.h>'
[ $fail -eq 0 ] && echo "check_layers self-test ok"
exit $fail
