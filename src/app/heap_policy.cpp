#include "app/heap_policy.h"

#include <malloc.h>

#include <cstdlib>
#include <cstring>

namespace capflow::app {

bool keep_freed_heap() {
  if (std::getenv("MALLOC_TRIM_THRESHOLD_")) return false;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "trim_threshold")) return false;
  constexpr int kThreshold = 64 << 20;  // bytes
  return mallopt(M_TRIM_THRESHOLD, kThreshold) == 1;
}

}  // namespace capflow::app
