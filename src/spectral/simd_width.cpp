#include "spectral/simd_width.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>

namespace capflow::spectral {

namespace {

// The width of the build's own flags: the kernels' baseline clone, and every kernel where there
// are no clones (CAPFLOW_NO_TARGET_CLONES, sanitizer builds).
constexpr int build_width() {
#if defined(__AVX512F__)
  return 8;
#elif defined(__AVX2__)
  return 4;
#else
  return 2;
#endif
}

int cpu_width() {
#if defined(CAPFLOW_NO_TARGET_CLONES)
  return build_width();
#else
  // the width of the clone the loader picks (the best listed level the CPU supports)
  __builtin_cpu_init();
#if !defined(CAPFLOW_CLONES_UP_TO_V3)
  if (__builtin_cpu_supports("x86-64-v4")) return 8;
#endif
  if (__builtin_cpu_supports("x86-64-v3")) return 4;
  return build_width();  // the baseline clone
#endif
}

std::atomic<int> g_limit{8};

}  // namespace

int simd_width() {
  static const int cpu = cpu_width();
  return std::min(cpu, g_limit.load(std::memory_order_relaxed));
}

const char* simd_width_name() {
  switch (simd_width()) {
    case 8:
      return "AVX-512, 8 doubles";
    case 4:
      return "AVX2, 4 doubles";
    default:
      return "SSE2, 2 doubles";
  }
}

void limit_simd_width(int w) {
  if (w != 8 && w != 4 && w != 2)
    throw std::invalid_argument("limit_simd_width: the width must be 8, 4 or 2, not " +
                                std::to_string(w));
  g_limit.store(w, std::memory_order_relaxed);
}

}  // namespace capflow::spectral
