#!/usr/bin/env bash
# The measured stability limits of fixed RK4 steps (benchmarks/capsule/stability_limits.cpp)
# over Ca, NB, NE, division and law, at the sphere and at steady states (made here by
# capflow steady): the table of docs/performance.md, "Fixed steps: the stability limit".
# Usage: benchmarks/capsule/stability_limits.sh BUILD_DIR [WORK_DIR]   (about 20 min, 2 cores)
set -euo pipefail
build=${1:?usage: stability_limits.sh BUILD_DIR [WORK_DIR]}
work=${2:-$(mktemp -d)}
probe=$build/benchmarks/capsule/stability_limits
capflow=$build/src/app/capflow
mkdir -p "$work"

limit() {  # law ne division nb ca [start.from]
  local law=$1 ne=$2 div=$3 nb=$4 ca=$5 from=${6:-}
  local c=$work/c_${law}_${ne}_${div}_${nb}_${ca}.json
  local start=""
  [ -n "$from" ] && start=", \"start\": {\"from\": \"$from\"}"
  printf '{"capsule": {"law": "%s"}, "mesh": {"elements": %s, "nb": %s, "division": "%s"},
    "flow": {"type": "planar-extension"}, "ca": %s%s}\n' "$law" "$ne" "$nb" "$div" "$ca" \
    "$start" > "$c"
  "$probe" "$c"
}

steady() {  # law ne division nb ca -> the run directory of its steady state
  local d=$work/steady_${1}_${2}_${3}_${4}_${5}
  printf '{"capsule": {"law": "%s"}, "mesh": {"elements": %s, "nb": %s, "division": "%s"},
    "flow": {"type": "planar-extension"}, "ca": %s, "output": {"mp4": false}}\n' \
    "$1" "$2" "$4" "$3" "$5" > "$d.json"
  "$capflow" steady "$d.json" -o "$d" --overwrite > "$d.log" 2>&1
  echo "$d"
}

echo "# at the sphere: NB, NE, division"
for nb in 6 8 10 12; do limit skalak 6 diagonal $nb 0.3; done
for nb in 8 10; do limit skalak 6 cube $nb 0.3; done
for nb in 8 10 12; do limit skalak 10 box $nb 0.3; done
limit skalak 10 cube 10 0.3
for nb in 8 10 12; do limit skalak 14 cube $nb 0.3; done
echo "# at the sphere: Ca and law"
for ca in 0.05 0.1 1 3; do limit skalak 6 diagonal 8 $ca; done
limit neo-hookean 6 diagonal 8 0.3
echo "# at steady states"
for ca in 0.3 1 2; do limit skalak 6 diagonal 8 $ca "$(steady skalak 6 diagonal 8 $ca)"; done
for ca in 0.2 0.35; do limit neo-hookean 6 diagonal 8 $ca "$(steady neo-hookean 6 diagonal 8 $ca)"; done
for ca in 0.45 1.5; do limit skalak 10 box 10 $ca "$(steady skalak 10 box 10 $ca)"; done
limit neo-hookean 10 box 10 0.3 "$(steady neo-hookean 10 box 10 0.3)"
echo "# fixed-step runs from rest at 0.9 and 1.1 times the measured limit (exit 0: ran to t_end,"
echo "# exit 4: the health check stopped the run)"
march() {  # law ne division nb ca
  local row h
  row=$(limit "$@")
  h=$(awk '{for (i = 1; i < NF; ++i) if ($i == "h*") print $(i + 1)}' <<< "$row")
  for f in 0.9 1.1; do
    local d=$work/march_${1}_${2}_${3}_${4}_${5}_$f dt
    dt=$(awk -v h="$h" -v f="$f" 'BEGIN {printf "%.6f", h * f}')
    printf '{"capsule": {"law": "%s"}, "mesh": {"elements": %s, "nb": %s, "division": "%s"},
      "flow": {"type": "planar-extension"}, "ca": %s, "time": {"dt": %s, "t_end": 4},
      "output": {"mp4": false}}\n' "$1" "$2" "$4" "$3" "$5" "$dt" > "$d.json"
    set +e
    "$capflow" run "$d.json" -o "$d" --overwrite > "$d.log" 2>&1
    local rc=$?
    set -e
    echo "$* dt = $f h* = $dt: exit $rc"
  done
}
march skalak 6 diagonal 8 0.3
march skalak 10 box 10 0.45
