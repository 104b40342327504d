// The heap policy of the capflow process (app/heap_policy.h): the trim threshold is raised
// unless the user set one in the environment.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "app/heap_policy.h"

namespace capflow::app {
namespace {

TEST(HeapPolicy, RaisesTheTrimThresholdUnlessTheUserSetOne) {
  const char* saved = std::getenv("GLIBC_TUNABLES");
  const std::string keep = saved ? saved : "";
  unsetenv("GLIBC_TUNABLES");
  setenv("MALLOC_TRIM_THRESHOLD_", "1000000", 1);
  EXPECT_FALSE(keep_freed_heap());
  unsetenv("MALLOC_TRIM_THRESHOLD_");
  setenv("GLIBC_TUNABLES", "glibc.malloc.trim_threshold=1000000", 1);
  EXPECT_FALSE(keep_freed_heap());
  setenv("GLIBC_TUNABLES", "glibc.malloc.arena_max=2", 1);
  EXPECT_TRUE(keep_freed_heap());
  unsetenv("GLIBC_TUNABLES");
  EXPECT_TRUE(keep_freed_heap());
  if (saved) setenv("GLIBC_TUNABLES", keep.c_str(), 1);
}

}  // namespace
}  // namespace capflow::app
