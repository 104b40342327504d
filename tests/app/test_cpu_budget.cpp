// The CPU budget of a movie run (app/cpu_budget.h): while the renderer is busy the solver's
// operators run with one thread fewer (at least one), otherwise uncapped, and the threads the cap
// leaves idle wait at nice 19 where the process may lower their nice value back; LP_NUM_THREADS
// is set only when the user has not set it.
#include <gtest/gtest.h>
#include <omp.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "app/cpu_budget.h"
#include "stokes/thread_cap.h"

namespace capflow::app {
namespace {

TEST(CpuBudget, ZeroSolverThreadsRestoresTheStartingCount) {
  // numerics.threads of one run must not carry into the next run in the same process (a sweep's
  // cases on a group of ranks run one after another in-process): 0 is the count the process
  // started with
  const int initial = omp_get_max_threads();
  set_solver_threads(initial == 1 ? 2 : 1);
  EXPECT_NE(omp_get_max_threads(), initial);
  set_solver_threads(0);
  EXPECT_EQ(omp_get_max_threads(), initial);
}

TEST(CpuBudget, BusyRendererTakesOneSolverThread) {
  const int threads = omp_get_max_threads();
  set_solver_threads(3);
  renderer_busy(true);
  EXPECT_EQ(stokes::thread_cap(), 2);
  renderer_busy(false);
  EXPECT_EQ(stokes::thread_cap(), 0);
  set_solver_threads(1);
  renderer_busy(true);
  EXPECT_EQ(stokes::thread_cap(), 1);  // never below one
  renderer_busy(false);
  EXPECT_EQ(stokes::thread_cap(), 0);
  set_solver_threads(threads);
}

// The nice value of each thread of the solver's team of `n` (the pool's threads in order).
std::vector<int> team_nice(int n) {
  std::vector<int> nice(n);
#pragma omp parallel num_threads(n)
  nice[omp_get_thread_num()] = getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
  return nice;
}

TEST(CpuBudget, IdleSolverThreadsWaitAtLowPriorityWhileAFrameIsPending) {
  const int threads = omp_get_max_threads();
  set_solver_threads(3);
  const bool may = start_solver_threads();
  const std::vector<int> before = team_nice(3);
  renderer_busy(true);  // cap 2: thread 2 idle from the next operator call on
  // unchanged until an operator call runs under the cap (the thread may still be working)
  EXPECT_EQ(team_nice(3), before);
  EXPECT_EQ(stokes::team_size(), 2);  // what an operator call does first
  const std::vector<int> busy = team_nice(3);
  renderer_busy(false);
  const std::vector<int> after = team_nice(3);
  EXPECT_EQ(busy[0], before[0]);
  EXPECT_EQ(busy[1], before[1]);
  EXPECT_EQ(busy[2], may ? 19 : before[2]);
  EXPECT_EQ(after, before);
  set_solver_threads(threads);
}

TEST(CpuBudget, RasteriserThreadsOnlyWhenUnset) {
  const char* before = std::getenv("LP_NUM_THREADS");
  const std::string saved = before ? before : "";
  setenv("LP_NUM_THREADS", "3", 1);
  EXPECT_FALSE(render_cpu_defaults());
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "3");
  unsetenv("LP_NUM_THREADS");
  EXPECT_TRUE(render_cpu_defaults());
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "1");
  if (before)
    setenv("LP_NUM_THREADS", saved.c_str(), 1);
  else
    unsetenv("LP_NUM_THREADS");
}

}  // namespace
}  // namespace capflow::app
