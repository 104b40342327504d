// Time per application of the single-layer operator (all nodes, one value per coincidence
// class), the double layer, and the octant subset (planar-extension symmetry), on the
// ellipsoid (1.8, 0.7, 1.0), default QuadratureOptions. Counters: kernel pairs per second (far +
// own + near points x targets) and the split of the pairs between the three tiers.
#include <benchmark/benchmark.h>
#include <omp.h>

#include "../common/fma_chains.h"
#include "geometry/mesh.h"
#include "geometry/shapes.h"
#include "stokes/boundary_integral.h"

using namespace capflow;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;

namespace {

struct Setup {
  geometry::Mesh mesh;
  stokes::BoundaryOperators op;
  Matrix3Xd x, f;
  Setup(int ne, int nb) : mesh(ne, nb), op(mesh) {
    x = geometry::map_points(mesh.reference(), geometry::ellipsoid_map(1.8, 0.7, 1.0));
    f.resize(3, mesh.num_local());
    for (int m = 0; m < mesh.num_local(); ++m)
      f.col(m) = Vector3d(std::sin(x(0, m)), x(1, m) * x(2, m), std::exp(0.5 * x(0, m)));
  }
};

void report(benchmark::State& st, const stokes::OperatorStats& s) {
  const double pairs = static_cast<double>(s.pairs());
  st.counters["pairs/s"] = benchmark::Counter(pairs * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["targets"] = static_cast<double>(s.targets);
  st.counters["own%"] = 100.0 * s.own_pairs / pairs;
  st.counters["near%"] = 100.0 * s.near_pairs / pairs;
  st.counters["far%"] = 100.0 * s.far_pairs / pairs;
  if (s.flops > 0)
    st.counters["flops"] =
        benchmark::Counter(s.flops * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["near/target"] = static_cast<double>(s.near_elements) / s.targets;
  st.counters["searches/target"] = static_cast<double>(s.searches) / s.targets;
}

void BM_SingleLayer(benchmark::State& st) {
  Setup s(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  stokes::OperatorStats stats;
  for (auto _ : st) benchmark::DoNotOptimize(s.op.single_layer(s.x, s.f, &stats));
  report(st, stats);
}

void BM_DoubleLayer(benchmark::State& st) {
  Setup s(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  stokes::OperatorStats stats;
  for (auto _ : st) benchmark::DoNotOptimize(s.op.double_layer(s.x, s.f, &stats));
  report(st, stats);
}

// Targets in the octant x, y, z >= 0 only (one per coincidence class).
std::vector<int> octant_targets(const geometry::Mesh& mesh) {
  std::vector<int> t;
  for (const auto& c : mesh.classes()) {
    const Vector3d p = mesh.reference().col(c.front());
    if (p.minCoeff() >= -1e-12) t.push_back(c.front());
  }
  return t;
}

void BM_SingleLayerOctant(benchmark::State& st) {
  Setup s(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  const std::vector<int> t = octant_targets(s.mesh);
  Matrix3Xd out;
  stokes::OperatorStats stats;
  for (auto _ : st) {
    s.op.single_layer(s.x, s.f, t, out, &stats);
    benchmark::DoNotOptimize(out.data());
  }
  report(st, stats);
}

// The double layer at the octant targets: one application (density form) against its assembly
// as a matrix (double_layer_matrix, every local node a column), the viscosity-ratio solve's
// two ways of applying it (capsule/viscosity_ratio.h).
void BM_DoubleLayerOctant(benchmark::State& st) {
  Setup s(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  const std::vector<int> t = octant_targets(s.mesh);
  Matrix3Xd out;
  stokes::OperatorStats stats;
  for (auto _ : st) {
    s.op.double_layer(s.x, s.f, t, out, &stats);
    benchmark::DoNotOptimize(out.data());
  }
  report(st, stats);
}
void BM_DoubleLayerMatrixOctant(benchmark::State& st) {
  Setup s(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  const std::vector<int> t = octant_targets(s.mesh);
  stokes::OperatorStats stats;
  for (auto _ : st) benchmark::DoNotOptimize(s.op.double_layer_matrix(s.x, t, nullptr, &stats));
  report(st, stats);
}

// The machine's peak (benchmarks/common/fma_chains.h): the reference for the fraction of peak of
// the counted single-layer flops (OperatorStats::flops).
using bench::fma_chains;
void BM_PeakFma(benchmark::State& st) {
  const int threads = static_cast<int>(st.range(0));
  constexpr long kIter = 1 << 20;
  for (auto _ : st) {
    double s = 0;
#pragma omp parallel num_threads(threads) reduction(+ : s)
    s += fma_chains(kIter);
    benchmark::DoNotOptimize(s);
  }
  st.counters["flops"] = benchmark::Counter(2.0 * 4 * 12 * kIter * threads * st.iterations(),
                                            benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(BM_PeakFma)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime();
BENCHMARK(BM_SingleLayer)
    ->ArgNames({"NE", "NB", "threads"})
    ->ArgsProduct({{6, 10, 14}, {8, 10, 12, 14}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5)
    ->UseRealTime();
BENCHMARK(BM_DoubleLayer)
    ->ArgNames({"NE", "NB", "threads"})
    ->ArgsProduct({{6, 10}, {10, 12}, {2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5)
    ->UseRealTime();
// The time stepper's use: octant targets (planar extension), NE=6 NB=10 (61 targets) and
// NE=10 NB=12 (157 targets). Run with --benchmark_repetitions=N for medians.
BENCHMARK(BM_SingleLayerOctant)
    ->ArgNames({"NE", "NB", "threads"})
    ->Args({6, 10, 1})
    ->Args({6, 10, 2})
    ->Args({10, 12, 1})
    ->Args({10, 12, 2})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5)
    ->UseRealTime();

BENCHMARK(BM_DoubleLayerOctant)
    ->ArgNames({"NE", "NB", "threads"})
    ->ArgsProduct({{6}, {8, 10}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5)
    ->UseRealTime();
BENCHMARK(BM_DoubleLayerMatrixOctant)
    ->ArgNames({"NE", "NB", "threads"})
    ->ArgsProduct({{6}, {8, 10}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5)
    ->UseRealTime();

BENCHMARK_MAIN();
