#!/usr/bin/env bash
# Velocity evaluation, an older build against a newer one (Milestone 9): runs the two
# bench_capsule binaries alternately ROUNDS times (Google Benchmark medians of 5 repetitions
# each), and prints per benchmark the median over the rounds of each build and their ratio.
# Usage: benchmarks/capsule/compare_builds.sh OLD_BENCH_CAPSULE NEW_BENCH_CAPSULE [ROUNDS] [FILTER]
# e.g. a build of the commit before the milestone in /tmp/base/build:
#   benchmarks/capsule/compare_builds.sh /tmp/base/build/benchmarks/capsule/bench_capsule \
#       build/benchmarks/capsule/bench_capsule 3
set -euo pipefail
old=$1 new=$2 rounds=${3:-3}
filter=${4:-'BM_Velocity(Box)?/NE:(6/NB:10|10/NB:12|14/NB:12)/'}
out=$(mktemp -d)
for r in $(seq "$rounds"); do
  for v in old new; do
    bin=$old; [ "$v" = new ] && bin=$new
    "$bin" --benchmark_filter="$filter" --benchmark_repetitions=5 \
      --benchmark_report_aggregates_only=true --benchmark_format=csv 2>/dev/null |
      awk -F, '/_median"/ {gsub(/"/, "", $1); sub(/_median$/, "", $1); print $1, $3}' \
        >"$out/$v.$r"
  done
done
python3 - "$out" "$rounds" <<'PY'
import sys, statistics, collections
d, rounds = sys.argv[1], int(sys.argv[2])
t = {v: collections.defaultdict(list) for v in ("old", "new")}
for v in t:
    for r in range(1, rounds + 1):
        for line in open(f"{d}/{v}.{r}"):
            name, ms = line.split()
            t[v][name].append(float(ms))  # the benchmarks report milliseconds
print(f"{'benchmark':52s} {'old ms':>9s} {'new ms':>9s} {'old/new':>8s}   per round old/new")
for name in t["old"]:
    o, n = t["old"][name], t["new"].get(name, [])
    if not n: continue
    mo, mn = statistics.median(o), statistics.median(n)
    per = " ".join(f"{a/b:.2f}" for a, b in zip(o, n))
    print(f"{name:52s} {mo:9.2f} {mn:9.2f} {mo/mn:8.2f}   {per}")
PY
rm -rf "$out"
