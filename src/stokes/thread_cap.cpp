#include "stokes/thread_cap.h"

#include <omp.h>

#include <algorithm>
#include <atomic>

namespace capflow::stokes {

namespace {
std::atomic<int> g_cap{0};
std::atomic<int> g_seen_cap{0};  // the cap the last operator call saw
std::atomic<void (*)(int)> g_observer{nullptr};
}  // namespace

void set_thread_cap(int threads) {
  g_cap.store(std::max(0, threads), std::memory_order_relaxed);
}

int thread_cap() {
  return g_cap.load(std::memory_order_relaxed);
}

void set_cap_observer(void (*observer)(int cap)) {
  g_observer.store(observer);
}

int team_size() {
  const int n = omp_get_max_threads(), cap = thread_cap();
  if (void (*observer)(int) = g_observer.load(); observer && omp_get_level() == 0)
    if (g_seen_cap.exchange(cap) != cap) observer(cap);
  return cap > 0 ? std::min(n, cap) : n;
}

}  // namespace capflow::stokes
