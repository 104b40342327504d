#!/usr/bin/env bash
# Velocity evaluation, an older build against a newer one (Milestone 9): for each benchmark that
# FILTER selects, runs the two bench_capsule (or bench_stokes) binaries one after the other
# (Google Benchmark medians of 5 repetitions each), ROUNDS rounds over all the benchmarks. A
# benchmark's old and new times of a round are thus seconds apart, so that the machine's slow and
# fast spells (up to 30 %, lasting minutes) fall on both. Prints per benchmark the median time
# of each build over the rounds, the median of the per-round ratios old/new and those ratios.
# Usage: benchmarks/capsule/compare_builds.sh OLD_BENCH NEW_BENCH [ROUNDS] [FILTER]
# e.g. a build of the commit before the milestone in /tmp/base/build:
#   benchmarks/capsule/compare_builds.sh /tmp/base/build/benchmarks/capsule/bench_capsule \
#       build/benchmarks/capsule/bench_capsule 3
set -euo pipefail
old=$1 new=$2 rounds=${3:-3}
filter=${4:-'BM_Velocity(Box)?/NE:(6/NB:10|10/NB:12|14/NB:12)/'}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mapfile -t names < <("$new" --benchmark_filter="$filter" --benchmark_list_tests)
[ ${#names[@]} -gt 0 ] || { echo "compare_builds.sh: no benchmark matches $filter" >&2; exit 2; }
for r in $(seq "$rounds"); do
  for name in "${names[@]}"; do
    for v in old new; do
      bin=$old; [ "$v" = new ] && bin=$new
      "$bin" --benchmark_filter="^${name}\$" --benchmark_repetitions=5 \
        --benchmark_report_aggregates_only=true --benchmark_format=csv 2>/dev/null |
        awk -F, -v r="$r" '/_median"/ {gsub(/"/, "", $1); sub(/_median$/, "", $1); print r, $1, $3}' \
          >>"$out/$v"
    done
  done
done
python3 - "$out" <<'PY'
import collections, statistics, sys
t = {v: collections.defaultdict(dict) for v in ("old", "new")}  # name -> {round: ms}
for v in t:
    for line in open(f"{sys.argv[1]}/{v}"):
        r, name, ms = line.split()
        t[v][name][int(r)] = float(ms)  # the benchmarks report milliseconds
print(f"{'benchmark':52s} {'old ms':>9s} {'new ms':>9s} {'old/new':>8s}   per round old/new")
for name, o in t["old"].items():
    n = t["new"].get(name, {})
    rounds = sorted(set(o) & set(n))
    if not rounds: continue
    ratios = [o[r] / n[r] for r in rounds]
    print(f"{name:52s} {statistics.median(o.values()):9.2f} {statistics.median(n.values()):9.2f} "
          f"{statistics.median(ratios):8.2f}   " + " ".join(f"{x:.2f}" for x in ratios))
PY
