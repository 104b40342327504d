// The CPU budget of a movie run (app/cpu_budget.h): while the renderer is busy the solver's
// operators run with one thread fewer (at least one), otherwise uncapped; LP_NUM_THREADS is set
// only when the user has not set it.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdlib>
#include <string>

#include "app/cpu_budget.h"
#include "stokes/thread_cap.h"

namespace capflow::app {
namespace {

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
