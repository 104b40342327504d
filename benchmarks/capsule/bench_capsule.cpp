// Time per RK4 step of the capsule dynamics (planar extension, Skalak C=1, lambda=1, the
// default options: octant symmetry, Hermite smoothing) and of its parts (traction, one
// velocity evaluation), on a deformed state reached from rest (Ca=0.45, t=0.5 at dt=5e-3),
// for NE=6/14 and NB=10/12 on 1 and 2 threads. Medians over repetitions: see scripts in
// docs/performance.md.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "../common/fma_chains.h"
#include "capsule/capsule.h"
#include "geometry/reference_shape.h"
#include "membrane/bending.h"
#include "red_cell.h"

using namespace capflow;

namespace {
constexpr double kCa = 0.45;

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

struct Setup {
  geometry::Mesh mesh;
  capsule::Capsule cap;
  Setup(int ne, int nb, geometry::Division division = geometry::Division::Cube)
      : mesh(ne, nb, geometry::ElementMap::Equiangular, division),
        cap(mesh, membrane::LawOptions{}, capsule::Flow::planar_extension()) {
    for (int k = 0; k < 100; ++k) cap.step(5e-3, [](double) { return kCa; });
  }
};

// One deformed state per (NE, NB, division), shared by the benchmarks.
Setup& setup(int ne, int nb, geometry::Division division = geometry::Division::Cube) {
  static std::map<std::tuple<int, int, int>, std::unique_ptr<Setup>> cache;
  auto& s = cache[{ne, nb, static_cast<int>(division)}];
  if (!s) s = std::make_unique<Setup>(ne, nb, division);
  return *s;
}

void BM_Step(benchmark::State& st) {
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  const Eigen::Matrix3Xd x0 = s.cap.positions();
  const double t0 = s.cap.time();
  for (auto _ : st) {
    s.cap.step(1e-3, [](double) { return kCa; });
    st.PauseTiming();
    s.cap.set_state(x0, t0, 0);
    st.ResumeTiming();
  }
}

void BM_Velocity(benchmark::State& st) {
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  for (auto _ : st) benchmark::DoNotOptimize(s.cap.velocity(s.cap.positions(), kCa));
}

// The velocity on the paper's box division (NE=10, the Milestone 8 branch benchmarks).
void BM_VelocityBox(benchmark::State& st) {
  Setup& s =
      setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)), geometry::Division::Box);
  omp_set_num_threads(static_cast<int>(st.range(2)));
  for (auto _ : st) benchmark::DoNotOptimize(s.cap.velocity(s.cap.positions(), kCa));
}

// The same velocity with the far Gauss order of before 2026-12-02 (nb + 3 instead of the
// default (3nb+19)/2): what the higher far order costs, measured in the same run.
void BM_VelocityFarNb3(benchmark::State& st) {
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  capsule::DynamicsOptions o;
  o.quadrature.nq_far = s.mesh.nb() + 3;
  const capsule::Capsule cap(s.mesh, membrane::LawOptions{}, capsule::Flow::planar_extension(), o);
  for (auto _ : st) benchmark::DoNotOptimize(cap.velocity(s.cap.positions(), kCa));
}

// Two threads against one in the same process, call by call: each iteration times one 1-thread
// and one 2-thread velocity evaluation back to back (in alternating order), so that the
// machine's slow and fast spells fall on both. Counters: the median times (ms) and the median
// of the per-pair ratios. Before each timed call an empty parallel region wakes the team, as
// the previous call of the same size would have left it spinning in BM_Velocity. The counter
// `machine` is the same ratio for a fixed amount of pure FMA work (fma_chains, ~1.6 ms on one
// thread, the same chains split between two), timed in the same iterations: how much of two
// cores the machine gave at that moment (2.0 when the two virtual CPUs have a core each).
// `fast_scaling` is the ratio of the 10th percentiles of the 1- and 2-thread times: the scaling
// of the calls that no neighbour on the machine slowed (a slowed 1-thread call alone gives
// per-pair ratios above 2, a slowed 2-thread call ratios far below).
void BM_VelocityThreadPairs(benchmark::State& st) {
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)),
                   static_cast<geometry::Division>(st.range(2)));
  const auto timed = [&](int threads) {
    omp_set_num_threads(threads);
#pragma omp parallel
    benchmark::ClobberMemory();
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(s.cap.velocity(s.cap.positions(), kCa));
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  // fixed FMA work, split between the threads
  const auto fma_timed = [](int threads) {
    constexpr long kIter = 1 << 20;
    const auto t0 = std::chrono::steady_clock::now();
    double sum = 0;
#pragma omp parallel num_threads(threads) reduction(+ : sum)
    sum += bench::fma_chains(kIter / threads);
    benchmark::DoNotOptimize(sum);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::vector<double> one, two, ratio, machine;
  for (auto _ : st) {
    const bool one_first = one.size() % 2 == 0;
    const double a = timed(one_first ? 1 : 2), b = timed(one_first ? 2 : 1);
    one.push_back(one_first ? a : b);
    two.push_back(one_first ? b : a);
    ratio.push_back(one.back() / two.back());
    const double fa = fma_timed(one_first ? 1 : 2), fb = fma_timed(one_first ? 2 : 1);
    machine.push_back(one_first ? fa / fb : fb / fa);
  }
  st.counters["one_ms"] = median(one);
  st.counters["two_ms"] = median(two);
  st.counters["scaling"] = median(ratio);
  st.counters["machine"] = median(machine);
  const auto p10 = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 10, v.end());
    return v[v.size() / 10];
  };
  st.counters["fast_scaling"] = p10(one) / p10(two);
}

void BM_Traction(benchmark::State& st) {
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  for (auto _ : st) benchmark::DoNotOptimize(s.cap.traction(s.cap.positions()));
}

// The bending load's share of a velocity evaluation (Milestone 15's budget: <= 15 % at NE = 6,
// NB = 10): a red blood cell (biconcave, Skalak C = 10, reference-model bending Eb = 5e-3) in
// simple shear at Ca = 0.1, deformed by 100 RK4 steps of dt = 5e-4. Each iteration times one
// Bending::load and one full velocity evaluation (which includes it) back to back, in
// alternating order; counters: their median times (ms) and the median per-pair ratio.
void BM_RedCellBendingShare(benchmark::State& st) {
  const geometry::Mesh mesh(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  const capsule::DynamicsOptions o = bench::red_cell_dynamics();
  const capsule::Capsule cap = bench::red_cell(mesh, 100, 5e-4, 0.1);
  const membrane::Bending bending(mesh, geometry::reference_positions(mesh, o.shape), o.bending);
  const Eigen::Matrix3Xd x = cap.positions();
  std::vector<double> load_ms, velocity_ms, ratio;
  const auto ms = [](auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  bool load_first = true;
  for (auto _ : st) {
    double l = 0, v = 0;
    const auto time_load = [&] { l = ms([&] { benchmark::DoNotOptimize(bending.load(x)); }); };
    const auto time_velocity = [&] { v = ms([&] { benchmark::DoNotOptimize(cap.velocity(x, 0.1)); }); };
    if (load_first) { time_load(); time_velocity(); } else { time_velocity(); time_load(); }
    load_first = !load_first;
    load_ms.push_back(l);
    velocity_ms.push_back(v);
    ratio.push_back(l / v);
  }
  st.counters["load_ms"] = median(load_ms);
  st.counters["velocity_ms"] = median(velocity_ms);
  st.counters["share"] = median(ratio);
}

void args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"NE", "NB", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const auto& [ne, nb] :
       std::initializer_list<std::pair<int, int>>{{6, 10}, {6, 12}, {14, 10}, {14, 12}})
    for (int th : {1, 2}) b->Args({ne, nb, th});
}
}  // namespace

BENCHMARK(BM_Step)->Apply(args);
BENCHMARK(BM_Velocity)->Apply(args);
BENCHMARK(BM_VelocityBox)
    ->ArgNames({"NE", "NB", "threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Args({10, 12, 1})
    ->Args({10, 12, 2});
BENCHMARK(BM_VelocityThreadPairs)
    ->ArgNames({"NE", "NB", "division"})
    ->Unit(benchmark::kMillisecond)
    ->Args({6, 10, static_cast<int>(geometry::Division::Cube)})
    ->Args({10, 12, static_cast<int>(geometry::Division::Box)})
    ->Args({14, 12, static_cast<int>(geometry::Division::Cube)});
BENCHMARK(BM_VelocityFarNb3)->Apply(args);
BENCHMARK(BM_Traction)->Apply(args);
BENCHMARK(BM_RedCellBendingShare)
    ->ArgNames({"NE", "NB", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->Args({6, 10, 1})
    ->Args({6, 10, 2})
    ->Args({6, 12, 2});
BENCHMARK_MAIN();
