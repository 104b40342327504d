#include "app/cpu_budget.h"

#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

#include "stokes/thread_buffers.h"
#include "stokes/thread_cap.h"

namespace capflow::app {

namespace {
std::atomic<int> g_solver_threads{0};  // 0: not set yet

// The solver team's threads (by OpenMP thread number, recorded by start_solver_threads) and
// their nice values then; whether their nice values may be lowered back after a frame.
std::mutex g_team_mu;
std::vector<pid_t> g_team_tids;
std::vector<int> g_team_nice;
bool g_may_renice = false;
constexpr int kIdleNice = 19;  // an idle solver thread's nice value while a frame is pending

// Whether this process may lower a thread's nice value back after raising it (CAP_SYS_NICE or a
// large enough RLIMIT_NICE): tried on a throwaway thread, so that no solver thread is left
// lowered.
bool may_restore_nice() {
  bool ok = false;
  std::thread([&ok] {
    const id_t tid = static_cast<id_t>(gettid());
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, tid);
    if (errno != 0 || nice >= kIdleNice) return;
    ok =
        setpriority(PRIO_PROCESS, tid, kIdleNice) == 0 && setpriority(PRIO_PROCESS, tid, nice) == 0;
  }).join();
  return ok;
}

// Threads [cap, team) sit idle in OpenMP's dock while the cap holds (libgomp gives a team of
// `cap` the pool's first threads); lowered to kIdleNice, their spinning there no longer takes
// the renderer's core half of the time. Restores the others' own nice values.
void renice_idle_threads(int cap) {
  for (size_t k = 1; k < g_team_tids.size(); ++k) {
    const bool idle = cap > 0 && static_cast<int>(k) >= cap;
    setpriority(PRIO_PROCESS, static_cast<id_t>(g_team_tids[k]), idle ? kIdleNice : g_team_nice[k]);
  }
}

// stokes' cap observer: called by the solver between its parallel regions when an operator call
// first runs under a new cap, when the threads the cap leaves out are idle (lowering them as the
// cap is set would starve one still working in the region in flight, and the region with it).
void on_cap_change(int cap) {
  std::lock_guard<std::mutex> l(g_team_mu);
  if (g_may_renice && cap > 0) renice_idle_threads(cap);
}
}  // namespace

void set_solver_threads(int threads) {
  // 0: the OpenMP default as the process started (OMP_NUM_THREADS, else all cores), taken before
  // any call changed it
  static const int initial = std::max(1, omp_get_max_threads());
  omp_set_num_threads(threads > 0 ? threads : initial);  // 0 also undoes an earlier run's count
  g_solver_threads.store(threads > 0 ? threads : initial, std::memory_order_relaxed);
}

bool start_solver_threads() {
  int n = g_solver_threads.load(std::memory_order_relaxed);
  if (n <= 0) n = std::max(1, omp_get_max_threads());
  stokes::prepare_thread_buffers(n);
  std::vector<pid_t> tids(n, 0);
  std::vector<int> nice(n, 0);
#pragma omp parallel num_threads(n)
  {
    const int k = omp_get_thread_num();
    tids[k] = gettid();
    nice[k] = getpriority(PRIO_PROCESS, static_cast<id_t>(tids[k]));
  }
  const bool may = may_restore_nice();
  std::lock_guard<std::mutex> l(g_team_mu);
  g_team_tids = std::move(tids);
  g_team_nice = std::move(nice);
  g_may_renice = may;
  stokes::set_cap_observer(on_cap_change);
  return may;
}

void renderer_busy(bool busy) {
  int n = g_solver_threads.load(std::memory_order_relaxed);
  if (n <= 0) n = std::max(1, omp_get_max_threads());
  if (busy) {
    stokes::set_thread_cap(std::max(1, n - 1));  // the idle threads lowered by on_cap_change
    return;
  }
  {
    std::lock_guard<std::mutex> l(g_team_mu);
    if (g_may_renice) renice_idle_threads(0);  // back first: the next call uses every thread
  }
  stokes::set_thread_cap(0);
}

bool render_cpu_defaults() {
  // Read by llvmpipe when its screen is created (the renderer's context); 1 hands the rasteriser
  // one thread while the render thread waits for it.
  if (std::getenv("LP_NUM_THREADS")) return false;
  return setenv("LP_NUM_THREADS", "1", 0) == 0;
}

}  // namespace capflow::app
