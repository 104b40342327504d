// capflow benchmarks: this machine's double-precision peak as code can reach it, 12 independent
// chains of 4-wide fused multiply-adds (x86-64-v3 and v4 clones, GCC vector extension) per
// thread, long enough to hide the FMA latency: 2 * 4 * 12 flops per iteration. No memory
// traffic, so its 2-thread against 1-thread time tells how much of two cores the machine gives
// at that moment (bench_stokes BM_PeakFma, bench_capsule BM_VelocityThreadPairs).
#pragma once

namespace capflow::bench {

typedef double v4d __attribute__((vector_size(32)));

__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"),
               noinline)) static double
fma_chains(long n) {
  v4d a[12];
  for (int k = 0; k < 12; ++k) a[k] = v4d{1.0 + k * 1e-3, 1.0, 1.0, 1.0};
  const v4d m = {0.999999, 0.999999, 0.999999, 0.999999}, c = {1e-6, 1e-6, 1e-6, 1e-6};
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < 12; ++k) a[k] = a[k] * m + c;
  double s = 0;
  for (int k = 0; k < 12; ++k) s += a[k][0] + a[k][1] + a[k][2] + a[k][3];
  return s;
}

}  // namespace capflow::bench
