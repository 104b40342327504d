#!/usr/bin/env bash
# The measured stability limits of fixed RK4 steps (benchmarks/capsule/stability_limits.cpp)
# over Ca, NB, NE, division and law, at steady states (made here by capflow steady): the table of docs/performance.md, "Fixed steps: the stability limit".
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

# A run's limit is the smallest along its path: for the Skalak law the steady state's (the limit
# falls as the capsule stretches: Ca=0.3 NE=6 NB=8, 0.032 at the sphere, 0.018 at the steady
# state), for the neo-Hookean law the sphere's (its membrane softens as it stretches).
at_steady() {  # law ne division nb ca
  limit "$@" "$(steady "$@")"
}
echo "# at the sphere (the first steps; the same for both laws, whose linearisations at rest agree)"
for nb in 6 8 10 12; do limit skalak 6 diagonal $nb 0.3; done
limit skalak 6 cube 8 0.3
for nb in 8 10 12; do limit skalak 10 box $nb 0.3; done
limit skalak 10 cube 10 0.3
for nb in 8 10 12; do limit skalak 14 cube $nb 0.3; done
for ca in 0.15 0.45 1 2; do limit skalak 6 diagonal 8 $ca; done
limit neo-hookean 6 diagonal 8 0.3
echo "# at steady states: NB, NE and division (Skalak C=1, Ca = 0.3)"
for nb in 6 8 10 12; do at_steady skalak 6 diagonal $nb 0.3; done
for nb in 8 10; do at_steady skalak 6 cube $nb 0.3; done
for nb in 8 10 12; do at_steady skalak 10 box $nb 0.3; done
at_steady skalak 10 cube 10 0.3
for nb in 8 10 12; do at_steady skalak 14 cube $nb 0.3; done
echo "# at steady states: Ca and law"
for ca in 0.15 0.45 1 2; do at_steady skalak 6 diagonal 8 $ca; done
for ca in 0.45 1; do at_steady skalak 10 box 10 $ca; done
for ca in 0.15 0.25 0.35; do at_steady neo-hookean 6 diagonal 8 $ca; done
at_steady neo-hookean 10 box 10 0.3
echo "# fixed-step runs from rest at 0.95 and 1.05 times the measured limit (exit 0: ran to t_end,"
echo "# exit 4: the health check stopped the run)"
march() {  # where law ne division nb ca  (where: limit = at the sphere, at_steady)
  local row h where=$1
  shift
  row=$($where "$@")
  h=$(awk '{for (i = 1; i < NF; ++i) if ($i == "h*") print $(i + 1)}' <<< "$row")
  for f in 0.95 1.05; do
    local d=$work/march_${1}_${2}_${3}_${4}_${5}_$f dt
    dt=$(awk -v h="$h" -v f="$f" 'BEGIN {printf "%.6f", h * f}')
    printf '{"capsule": {"law": "%s"}, "mesh": {"elements": %s, "nb": %s, "division": "%s"},
      "flow": {"type": "planar-extension"}, "ca": %s, "time": {"dt": %s, "t_end": 15},
      "output": {"mp4": false}}\n' "$1" "$2" "$4" "$3" "$5" "$dt" > "$d.json"
    set +e
    "$capflow" run "$d.json" -o "$d" --overwrite > "$d.log" 2>&1
    local rc=$?
    set -e
    echo "$* dt = $f h* = $dt: exit $rc"
  done
}
march at_steady skalak 6 diagonal 8 0.3
march at_steady skalak 10 box 10 0.45
march limit neo-hookean 6 diagonal 8 0.3
