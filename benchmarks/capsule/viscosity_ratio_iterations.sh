#!/usr/bin/env bash
# Milestone 10: GMRES iterations of the viscosity-ratio solve per velocity evaluation against
# lambda. Runs a Skalak capsule (C = 1, Ca = 0.45, planar extension, NE=6 NB=8, default adaptive
# steps) from rest to t = T for each lambda and prints, from the run's last log line, the
# velocity evaluations, the GMRES iterations and the wall time; and the cost per step: the run to T
# against the same run to T/5 (wall difference over step difference, which removes the set-up),
# relative to lambda = 1 in the same round (ROUNDS rounds, default 3; the median of the ratios).
# Usage: [NB=8] [ROUNDS=3] benchmarks/capsule/viscosity_ratio_iterations.sh [BUILD_DIR] [T] [LAMBDAS]
#   (defaults: build, 0.5, "0.01 0.1 0.2 0.5 1 2 5 10 100"; 1 is always run first)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
t_end=${2:-0.5}
nb=${NB:-8}  # NB=... in the environment: another resolution
exe="$build/src/app/capflow"
[ -x "$exe" ] || { echo "viscosity_ratio_iterations: $exe not built" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
lambdas=${3:-"0.01 0.1 0.2 0.5 1 2 5 10 100"}
t_short=$(awk -v t="$t_end" 'BEGIN { print t / 5 }')
# run LAMBDA T: the run's last log line; its wall time (s, from the clock) in $out/wall
run() {
  cat > "$out/control.json" <<JSON
{"ca": 0.45, "capsule": {"law": "skalak", "C": 1, "viscosity_ratio": $1},
 "mesh": {"elements": 6, "nb": $nb}, "flow": {"type": "planar-extension"},
 "time": {"t_end": $2}, "output": {"png": false, "mp4": false}}
JSON
  local t0 t1
  t0=$(date +%s.%N)
  "$exe" run "$out/control.json" -o "$out/run" 2>&1 | grep "^end (" || true
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }' > "$out/wall"
  rm -rf "$out/run"
}
steps_of() { sed -n 's/.* steps=\([0-9]*\) .*/\1/p' <<<"$1"; }
# ROUNDS rounds, each running every lambda in turn (lambda = 1 first): the per-step cost of a
# lambda against lambda = 1 of the same round, and the median over the rounds
rounds=${ROUNDS:-3}
order="1 $(tr ' ' '\n' <<<"$lambdas" | grep -vx 1 | tr '\n' ' ')"
for r in $(seq "$rounds"); do
  for lambda in $order; do
    short=$(run "$lambda" "$t_short")
    wall_short=$(cat "$out/wall")
    line=$(run "$lambda" "$t_end")
    wall_long=$(cat "$out/wall")
    awk -v a="$wall_short" -v b="$wall_long" -v s="$(steps_of "$short")" \
      -v l="$(steps_of "$line")" 'BEGIN { printf "%.3f\n", 1000 * (b - a) / (l - s) }' \
      >>"$out/per_step.$lambda"
    echo "$wall_long" >>"$out/wall.$lambda"
    echo "$line" >"$out/line.$lambda"
  done
done
echo "| lambda | steps | velocity evaluations | GMRES iterations | per evaluation | D at t = $t_end | wall s (median) | ms per step (median) | per step / lambda = 1, per round | median |"
echo "|---|---|---|---|---|---|---|---|---|---|"
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
for lambda in $order; do
  line=$(cat "$out/line.$lambda")
  ratios=$(paste "$out/per_step.$lambda" "$out/per_step.1" | awk '{ printf "%.2f\n", $1 / $2 }')
  steps=$(steps_of "$line")
  evals=$(sed -n 's/.*velocity evaluations=\([0-9]*\).*/\1/p' <<<"$line")
  iters=$(sed -n 's/.*GMRES iterations \([0-9]*\),.*/\1/p' <<<"$line")
  per=$(sed -n 's/.*, \([0-9.]*\) per evaluation.*/\1/p' <<<"$line")
  d=$(sed -n 's/.* D=\([0-9.]*\) .*/\1/p' <<<"$line")
  printf '| %s | %s | %s | %s | %s | %s | %.3f | %.2f | %s | %.2f |\n' "$lambda" "$steps" \
    "$evals" "${iters:-0}" "${per:-0}" "$d" "$(median <"$out/wall.$lambda")" \
    "$(median <"$out/per_step.$lambda")" "$(tr '\n' ' ' <<<"$ratios" | sed 's/ $//')" \
    "$(median <<<"$ratios")"
done
