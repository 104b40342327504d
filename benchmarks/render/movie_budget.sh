#!/usr/bin/env bash
# Milestone 13: a movie run against the same run without frames. Runs the three control files
# (no frames, MP4, MP4 + PNG: Skalak Ca=0.45, NE=6, NB=9, dt=0.004, 600 steps, a 1280x720 frame
# every 10 steps) alternately ROUNDS times with /usr/bin/time and prints the medians of wall and
# CPU (user + sys) time, the ratios to the run without frames (each round's ratio, and the median),
# and the renderer's wall ms per frame by stage from the movie runs' run.log.
# Usage: benchmarks/render/movie_budget.sh [BUILD_DIR] [ROUNDS]   (defaults: build, 5)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
rounds=${2:-5}
exe="$build/src/app/capflow"
[ -x "$exe" ] || { echo "movie_budget: $exe not built" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for r in $(seq "$rounds"); do
  for c in noframes mp4 mp4png; do
    /usr/bin/time -f "%e %U %S" -o "$out/time" "$exe" run "benchmarks/render/movie_$c.json" \
      -o "$out/run_$c" > /dev/null 2>&1
    echo "$r $c $(cat "$out/time")" >> "$out/times"
    grep -o "ms per frame.*" "$out/run_$c/run.log" >> "$out/stages_$c" || true
    rm -rf "$out/run_$c"
  done
done
python3 - "$out" <<'PY'
import sys, statistics, collections
d = sys.argv[1]
rows = collections.defaultdict(dict)
for line in open(f"{d}/times"):
    r, c, wall, user, sys_ = line.split()
    rows[int(r)][c] = (float(wall), float(user) + float(sys_))
print("| run | wall s (median) | CPU s (median) | wall / no frames (median) | per round |")
print("|---|---|---|---|---|")
for c, name in (("noframes", "no frames"), ("mp4", "MP4"), ("mp4png", "MP4 + PNG")):
    walls = [rows[r][c][0] for r in sorted(rows)]
    cpus = [rows[r][c][1] for r in sorted(rows)]
    ratios = [rows[r][c][0] / rows[r]["noframes"][0] for r in sorted(rows)]
    print(f"| {name} | {statistics.median(walls):.2f} | {statistics.median(cpus):.2f} | "
          f"{statistics.median(ratios):.3f} | {' '.join(f'{x:.2f}' for x in ratios)} |")
for c in ("mp4", "mp4png"):
    try:
        lines = open(f"{d}/stages_{c}").read().strip().splitlines()
    except FileNotFoundError:
        lines = []
    if lines:  # builds before Milestone 13 do not log the stages
        print(f"\n{c}: renderer {lines[len(lines) // 2]} (the median round's log)")
PY
