#include "stokes/thread_cap.h"

#include <omp.h>

#include <algorithm>
#include <atomic>

namespace capflow::stokes {

namespace {
std::atomic<int> g_cap{0};
}

void set_thread_cap(int threads) {
  g_cap.store(std::max(0, threads), std::memory_order_relaxed);
}

int thread_cap() {
  return g_cap.load(std::memory_order_relaxed);
}

int team_size() {
  const int n = omp_get_max_threads(), cap = thread_cap();
  return cap > 0 ? std::min(n, cap) : n;
}

}  // namespace capflow::stokes
