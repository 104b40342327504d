// Time per RK4 step of the capsule dynamics (planar extension, Skalak C=1, lambda=1, the
// default options: octant symmetry, Hermite smoothing) and of its parts (traction, one
// velocity evaluation), on a deformed state reached from rest (Ca=0.45, t=0.5 at dt=5e-3),
// for NE=6/14 and NB=10/12 on 1 and 2 threads. Medians over repetitions: see scripts in
// docs/performance.md.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <map>
#include <memory>
#include <tuple>

#include "capsule/capsule.h"

using namespace capflow;

namespace {
constexpr double kCa = 0.45;

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
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)),
                   geometry::Division::Box);
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

void BM_Traction(benchmark::State& st) {
  Setup& s = setup(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  omp_set_num_threads(static_cast<int>(st.range(2)));
  for (auto _ : st) benchmark::DoNotOptimize(s.cap.traction(s.cap.positions()));
}

void args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"NE", "NB", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const auto& [ne, nb] : std::initializer_list<std::pair<int, int>>{{6, 10}, {6, 12}, {14, 10}, {14, 12}})
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
BENCHMARK(BM_VelocityFarNb3)->Apply(args);
BENCHMARK(BM_Traction)->Apply(args);
BENCHMARK_MAIN();
