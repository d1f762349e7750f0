#!/bin/sh
# The physics' floors (docs/architecture.md, server/physics by concern): a
# folder includes only folders on floors below its own, or itself. Floor 3
# (what reads a model) may include within itself and the root.
#   0  base simd
#   1  ground collision road_car   what the model is made of
#   2  core                        Model, State, Workspace
#   3  build forces integrators kernels checks, the root (simulator.*)
# Usage: physics_floors.sh <server/physics>; prints every include that runs
# up or across a floor and exits 1 if there is one.
set -eu
root=${1:?usage: physics_floors.sh <server/physics>}
floor() {
  case $1 in
    base|simd) echo 0 ;;
    ground|collision|road_car) echo 1 ;;
    core) echo 2 ;;
    build|forces|integrators|kernels|checks|.) echo 3 ;;
    *) echo unknown ;;
  esac
}
bad=0
checked=0
for file in $(cd "$root" && find . -name '*.hpp' -o -name '*.cpp' | sed 's#^\./##' | sort); do
  dir=$(dirname "$file")
  from=$(floor "$dir")
  if [ "$from" = unknown ]; then
    echo "$file: folder '$dir' has no floor (add it to physics_floors.sh and docs/architecture.md)"
    bad=1
    continue
  fi
  for inc in $(sed -n 's#^[[:space:]]*\#include[[:space:]]*"physics/\([^"]*\)".*#\1#p' "$root/$file"); do
    checked=$((checked + 1))
    case $inc in */*) to_dir=${inc%/*} ;; *) to_dir=. ;; esac
    [ "$to_dir" = "$dir" ] && continue
    to=$(floor "$to_dir")
    if [ "$to" = unknown ] || [ "$to" -gt "$from" ] || { [ "$to" -eq "$from" ] && [ "$from" -lt 3 ]; }; then
      echo "$file (floor $from) includes physics/$inc (floor $to)"
      bad=1
    fi
  done
done
echo "physics floors: $checked includes checked"
exit $bad
