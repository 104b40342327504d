// The heap policy of the capflow process (app/heap_policy.h): the trim and mmap thresholds are
// raised unless the user set them in the environment.
#include <gtest/gtest.h>
#include <malloc.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "app/heap_policy.h"

namespace capflow::app {
namespace {

// Keeps the test's blocks in use (the compiler may drop a malloc whose block is never read).
void* volatile g_sink = nullptr;

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
  setenv("MALLOC_MMAP_THRESHOLD_", "1000000", 1);
  EXPECT_FALSE(keep_freed_heap());
  unsetenv("MALLOC_MMAP_THRESHOLD_");
  setenv("GLIBC_TUNABLES", "glibc.malloc.mmap_threshold=1000000", 1);
  EXPECT_FALSE(keep_freed_heap());
  unsetenv("GLIBC_TUNABLES");
  EXPECT_TRUE(keep_freed_heap());
  if (saved) setenv("GLIBC_TUNABLES", keep.c_str(), 1);
}

TEST(HeapPolicy, BlocksOfAMegabyteComeFromTheHeapNotFromFreshMappings) {
  // glibc maps blocks above its mmap threshold (128 KiB by default, fixed once the trim threshold
  // is set) one by one; under the policy a 1 MiB block is heap memory, reused after a free.
  if (std::getenv("MALLOC_MMAP_THRESHOLD_") || std::getenv("MALLOC_TRIM_THRESHOLD_") ||
      std::getenv("GLIBC_TUNABLES"))
    GTEST_SKIP() << "the environment sets malloc thresholds";
  ASSERT_TRUE(keep_freed_heap());
  const size_t mapped = mallinfo2().hblkhd;
  for (int k = 0; k < 3; ++k) {
    void* p = std::malloc(1 << 20);
    ASSERT_NE(p, nullptr);
    std::memset(p, 1, 1 << 20);
    g_sink = p;
    EXPECT_EQ(mallinfo2().hblkhd, mapped) << "a 1 MiB block was mapped";
    std::free(p);
  }
}

}  // namespace
}  // namespace capflow::app
