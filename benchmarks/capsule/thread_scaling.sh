#!/usr/bin/env bash
# Two threads against one for the velocity evaluation (Milestone 9): runs bench_capsule ROUNDS
# times; in each run Google Benchmark times the 1- and 2-thread variants back to back (medians
# of 5 repetitions each), and their ratio is that round's scaling. Prints per case the median
# times over the rounds, the median of the per-round ratios and the ratios themselves.
# Usage: benchmarks/capsule/thread_scaling.sh [BENCH_CAPSULE] [ROUNDS] [FILTER]
set -euo pipefail
bin=${1:-build/benchmarks/capsule/bench_capsule} rounds=${2:-7}
filter=${3:-'BM_Velocity(Box)?/NE:(6/NB:10|10/NB:12|14/NB:12)/'}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for r in $(seq "$rounds"); do
  "$bin" --benchmark_filter="$filter" --benchmark_repetitions=5 \
    --benchmark_report_aggregates_only=true --benchmark_format=csv 2>/dev/null |
    awk -F, -v r="$r" '/_median"/ {gsub(/"/, "", $1); sub(/_median$/, "", $1); print r, $1, $3}' \
      >>"$out"
done
python3 - "$out" <<'PY'
import collections, re, statistics, sys
ms = collections.defaultdict(dict)  # (case, threads) -> {round: ms}
for line in open(sys.argv[1]):
    r, name, t = line.split()
    m = re.match(r"(.*)/threads:(\d+)/real_time$", name)
    if m:
        ms[(m.group(1), int(m.group(2)))][int(r)] = float(t)
print(f"{'case':34} {'1 thread ms':>11} {'2 threads ms':>12} {'scaling':>8}   per round")
for case in dict.fromkeys(c for c, _ in ms):
    one, two = ms.get((case, 1), {}), ms.get((case, 2), {})
    rounds = sorted(set(one) & set(two))
    if not rounds:
        continue
    ratios = [one[r] / two[r] for r in rounds]
    print(f"{case:34} {statistics.median(one.values()):11.2f} "
          f"{statistics.median(two.values()):12.2f} {statistics.median(ratios):8.2f}   " +
          " ".join(f"{x:.2f}" for x in ratios))
PY
