#!/usr/bin/env bash
# Milestone 10: GMRES iterations of the viscosity-ratio solve per velocity evaluation against
# lambda. Runs a Skalak capsule (C = 1, Ca = 0.45, planar extension, NE=6 NB=8, default adaptive
# steps) from rest to t = T for each lambda and prints, from the run's last log line, the
# velocity evaluations, the GMRES iterations and the wall time.
# Usage: benchmarks/capsule/viscosity_ratio_iterations.sh [BUILD_DIR] [T]   (defaults: build, 0.5)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
t_end=${2:-0.5}
exe="$build/src/app/capflow"
[ -x "$exe" ] || { echo "viscosity_ratio_iterations: $exe not built" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| lambda | steps | velocity evaluations | GMRES iterations | per evaluation | D at t = $t_end | wall s |"
echo "|---|---|---|---|---|---|---|"
for lambda in 0.01 0.1 0.2 0.5 1 2 5 10 100; do
  cat > "$out/control.json" <<JSON
{"ca": 0.45, "capsule": {"law": "skalak", "C": 1, "viscosity_ratio": $lambda},
 "mesh": {"elements": 6, "nb": 8}, "flow": {"type": "planar-extension"},
 "time": {"t_end": $t_end}, "output": {"png": false, "mp4": false}}
JSON
  line=$("$exe" run "$out/control.json" -o "$out/run" 2>&1 | grep "^end (" || true)
  rm -rf "$out/run"
  steps=$(sed -n 's/.* steps=\([0-9]*\) .*/\1/p' <<<"$line")
  evals=$(sed -n 's/.*velocity evaluations=\([0-9]*\).*/\1/p' <<<"$line")
  iters=$(sed -n 's/.*GMRES iterations \([0-9]*\),.*/\1/p' <<<"$line")
  per=$(sed -n 's/.*, \([0-9.]*\) per evaluation.*/\1/p' <<<"$line")
  d=$(sed -n 's/.* D=\([0-9.]*\) .*/\1/p' <<<"$line")
  wall=$(sed -n 's/.* wall=\([0-9.]*\) s.*/\1/p' <<<"$line")
  echo "| $lambda | $steps | $evals | ${iters:-0} | ${per:-0} | $d | $wall |"
done
