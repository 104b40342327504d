#include "app/cpu_budget.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>

#include "stokes/thread_buffers.h"
#include "stokes/thread_cap.h"

namespace capflow::app {

namespace {
std::atomic<int> g_solver_threads{0};  // 0: not set yet
}

void set_solver_threads(int threads) {
  // 0: the OpenMP default as the process started (OMP_NUM_THREADS, else all cores), taken before
  // any call changed it
  static const int initial = std::max(1, omp_get_max_threads());
  if (threads > 0) omp_set_num_threads(threads);
  g_solver_threads.store(threads > 0 ? threads : initial, std::memory_order_relaxed);
}

void start_solver_threads() {
  int n = g_solver_threads.load(std::memory_order_relaxed);
  if (n <= 0) n = std::max(1, omp_get_max_threads());
  stokes::prepare_thread_buffers(n);
}

void renderer_busy(bool busy) {
  int n = g_solver_threads.load(std::memory_order_relaxed);
  if (n <= 0) n = std::max(1, omp_get_max_threads());
  stokes::set_thread_cap(busy ? std::max(1, n - 1) : 0);
}

bool render_cpu_defaults() {
  // Read by llvmpipe when its screen is created (the renderer's context); 1 hands the rasteriser
  // one thread while the render thread waits for it.
  if (std::getenv("LP_NUM_THREADS")) return false;
  return setenv("LP_NUM_THREADS", "1", 0) == 0;
}

}  // namespace capflow::app
