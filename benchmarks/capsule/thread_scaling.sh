#!/usr/bin/env bash
# Two threads against one for the velocity evaluation (Milestone 9). Runs bench_capsule's
# BM_VelocityThreadPairs ROUNDS times: inside a run each iteration times a 1-thread and a
# 2-thread call back to back (so that the machine's slow spells fall on both), and the run's
# scaling is the median of those per-pair ratios. Prints per case the median times and scaling
# over the rounds and each round's scaling, with the machine's own scaling of pure FMA work timed
# in the same iterations (the counter `machine`: 2.0 when the two virtual CPUs have a core each)
# and the ratio of the 10th percentiles of the two times (`fast`: the calls no neighbour on the
# machine slowed). Several binaries (comma-separated) run in turn in every round, so that their
# rounds share the machine's states.
# Usage: benchmarks/capsule/thread_scaling.sh [BENCH_CAPSULE[,BENCH_CAPSULE...]] [ROUNDS] [FILTER]
set -euo pipefail
IFS=, read -r -a bins <<<"${1:-build/benchmarks/capsule/bench_capsule}"
rounds=${2:-5} filter=${3:-'BM_VelocityThreadPairs/'}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for r in $(seq "$rounds"); do
  for b in "${!bins[@]}"; do
    "${bins[$b]}" --benchmark_filter="$filter" --benchmark_min_time=2 --benchmark_format=json \
      >"$out/$b.$r.json" 2>/dev/null
  done
done
python3 - "$out" "$rounds" "${bins[@]}" <<'PY'
import collections, json, statistics, sys
d, rounds, bins = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
for b, path in enumerate(bins):
    # case -> per round (1 thread ms, 2 threads ms, scaling, machine, fast)
    runs = collections.defaultdict(list)
    for r in range(1, rounds + 1):
        for x in json.load(open(f"{d}/{b}.{r}.json"))["benchmarks"]:
            runs[x["name"]].append((x["one_ms"], x["two_ms"], x["scaling"], x["machine"],
                                    x["fast_scaling"]))
    print(path)
    print(f"{'case':44} {'1 thread ms':>11} {'2 threads ms':>12} {'scaling':>8} {'machine':>8}"
          f" {'fast':>6}   per round: scaling (machine) [fast]")
    for case, v in runs.items():
        med = [statistics.median(x[i] for x in v) for i in range(5)]
        print(f"{case:44} {med[0]:11.2f} {med[1]:12.2f} {med[2]:8.2f} {med[3]:8.2f} {med[4]:6.2f}"
              "   " + " ".join(f"{x[2]:.2f} ({x[3]:.2f}) [{x[4]:.2f}]" for x in v))
PY
