#include "app/cpu_budget.h"

#include <omp.h>
#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
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

int creatable_threads(int wanted) {
  struct Gate {
    std::mutex mu;
    std::condition_variable cv;
    bool open = false;
  } gate;
  const auto wait = [](void* p) -> void* {
    Gate& g = *static_cast<Gate*>(p);
    std::unique_lock<std::mutex> l(g.mu);
    g.cv.wait(l, [&] { return g.open; });
    return nullptr;
  };
  std::vector<pthread_t> started;
  started.reserve(static_cast<size_t>(std::max(0, wanted - 1)));
  for (int k = 1; k < wanted; ++k) {
    pthread_t t;
    if (pthread_create(&t, nullptr, +wait, &gate) != 0) break;
    started.push_back(t);
  }
  {
    std::lock_guard<std::mutex> l(gate.mu);
    gate.open = true;
  }
  gate.cv.notify_all();
  for (pthread_t t : started) pthread_join(t, nullptr);
  return static_cast<int>(started.size()) + 1;
}

int set_solver_threads(int threads, std::string* warning) {
  // 0: the OpenMP default as the process started (OMP_NUM_THREADS, else all cores), taken before
  // any call changed it
  static const int initial = std::max(1, omp_get_max_threads());
  int n = threads > 0 ? threads : initial;  // 0 also undoes an earlier run's count
  if (warning) warning->clear();
  // A count above what already ran is tried first: libgomp cannot fall back, it ends the process
  // when a thread does not start.
  static int proven = 1;
  if (n > proven) {
    const int can = creatable_threads(n);
    if (can < n) {
      // Half of them: the limit was processes or memory (thread stacks), and the solver's
      // per-thread buffers, the renderer and llvmpipe need their share of it too.
      const int use = std::max(1, can / 2);
      if (warning)
        *warning = "numerics.threads " + std::to_string(n) + ": this process can start only " +
                   std::to_string(can) + " threads (a limit on processes or memory); using " +
                   std::to_string(use);
      n = use;
    }
    proven = std::max(proven, n);
  }
  omp_set_num_threads(n);
  g_solver_threads.store(n, std::memory_order_relaxed);
  return n;
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
  // Several renderers (the movie's, the live console's) may be busy at once: the cap holds until
  // the last of them is idle.
  static std::atomic<int> busy_count{0};
  int n = g_solver_threads.load(std::memory_order_relaxed);
  if (n <= 0) n = std::max(1, omp_get_max_threads());
  if (busy) {
    if (busy_count.fetch_add(1) == 0)
      stokes::set_thread_cap(std::max(1, n - 1));  // the idle threads lowered by on_cap_change
    return;
  }
  if (busy_count.fetch_sub(1) != 1) return;
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
