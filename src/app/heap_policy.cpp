#include "app/heap_policy.h"

#include <malloc.h>

#include <cstdlib>
#include <cstring>

namespace capflow::app {

namespace {
// Whether the environment sets one of glibc's malloc thresholds (MALLOC_<NAME>_ or
// GLIBC_TUNABLES glibc.malloc.<name>).
bool user_sets(const char* env, const char* tunable) {
  if (std::getenv(env)) return true;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  return tunables && std::strstr(tunables, tunable);
}
}  // namespace

bool keep_freed_heap() {
  bool ok = true;
  if (user_sets("MALLOC_TRIM_THRESHOLD_", "trim_threshold"))
    ok = false;
  else
    ok = mallopt(M_TRIM_THRESHOLD, 64 << 20) == 1;  // bytes
  if (user_sets("MALLOC_MMAP_THRESHOLD_", "mmap_threshold"))
    ok = false;
  else
    ok = mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1 && ok;  // glibc's largest on 64-bit
  return ok;
}

}  // namespace capflow::app
