#!/usr/bin/env bash
# Fails when an #include crosses the layers of docs architecture.md:
#   core/      : no nav/, sim/, scenarios/, Bullet, GL/OSMesa, YAML, assimp, urdf, OMPL
#   nav/       : no sim/, scenarios/, Bullet, GL, YAML, assimp, urdf
#   sim/ public headers (*.h): no Bullet, GL/OSMesa, assimp or urdf types
#   only scenarios/ (and tests/) may include yaml-cpp
set -u
root=${1:-.}
cd "$root" || exit 2
status=0

check() {  # check DESCRIPTION PATTERN FILES...
  local what=$1 pattern=$2
  shift 2
  [ $# -eq 0 ] && return
  local hits
  hits=$(grep -HnE "^[[:space:]]*#[[:space:]]*include[[:space:]]*[<\"]($pattern)" "$@" 2>/dev/null)
  if [ -n "$hits" ]; then
    echo "layer violation: $what"
    echo "$hits"
    status=1
  fi
}

mapfile -t core_files < <(find core -name '*.h' -o -name '*.cc' 2>/dev/null | sort)
mapfile -t nav_files < <(find nav -name '*.h' -o -name '*.cc' 2>/dev/null | sort)
mapfile -t sim_headers < <(find sim -name '*.h' 2>/dev/null | sort)
mapfile -t sim_files < <(find sim -name '*.h' -o -name '*.cc' 2>/dev/null | sort)

third_party='btBullet|Bullet|bullet/|LinearMath|BulletCollision|BulletDynamics|GL/|yaml-cpp|assimp|urdf'
check "core/ must not include nav/, sim/, scenarios/ or third-party simulation libraries" \
  "nav/|sim/|scenarios/|ompl/|$third_party" "${core_files[@]}"
check "nav/ must not include sim/ or scenarios/ or simulation libraries" \
  "sim/|scenarios/|$third_party" "${nav_files[@]}"
check "public sim/ headers must not expose Bullet, GL, assimp or urdf types" \
  "btBullet|bt[A-Z]|Bullet|LinearMath|GL/|assimp|urdf" "${sim_headers[@]}"
check "sim/ must not include scenarios/ or read YAML" "scenarios/|yaml-cpp" "${sim_files[@]}"

if [ $status -eq 0 ]; then
  echo "layer includes ok (${#core_files[@]} core, ${#nav_files[@]} nav, ${#sim_files[@]} sim files)"
fi
exit $status
