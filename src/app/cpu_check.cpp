// The CPU check: a binary built for the build machine's instruction set (CAPFLOW_ARCH_FLAGS,
// -march=native by default) stops with a message naming the missing extension and the rebuild,
// instead of dying on an illegal instruction, when it is started on an older CPU (a cluster's
// compute nodes older than its login node). It runs as a constructor of priority 101, before
// the C++ static initialisers that could already use the extensions.
#include <cstdio>
#include <cstdlib>

namespace {

[[noreturn]] void missing(const char* extension) {
  std::fprintf(stderr,
               "capflow: this binary was built with %s and uses the CPU extension %s, which this "
               "CPU does not have. Build capflow on this machine (scripts/build), or configure "
               "with -DCAPFLOW_ARCH_FLAGS=-march=x86-64-v2 for a binary that runs on any "
               "x86-64-v2 CPU.\n",
               CAPFLOW_ARCH_FLAGS, extension);
  std::_Exit(1);
}

// __builtin_cpu_supports takes string literals only
#define CAPFLOW_REQUIRE(ext) \
  if (!__builtin_cpu_supports(ext)) missing(ext)

__attribute__((constructor(101))) void check_cpu() {
  __builtin_cpu_init();
#ifdef __SSE4_2__
  CAPFLOW_REQUIRE("sse4.2");
#endif
#ifdef __POPCNT__
  CAPFLOW_REQUIRE("popcnt");
#endif
#ifdef __AVX__
  CAPFLOW_REQUIRE("avx");
#endif
#ifdef __AVX2__
  CAPFLOW_REQUIRE("avx2");
#endif
#ifdef __FMA__
  CAPFLOW_REQUIRE("fma");
#endif
#ifdef __BMI2__
  CAPFLOW_REQUIRE("bmi2");
#endif
#ifdef __AVX512F__
  CAPFLOW_REQUIRE("avx512f");
#endif
#ifdef __AVX512VL__
  CAPFLOW_REQUIRE("avx512vl");
#endif
#ifdef __AVX512BW__
  CAPFLOW_REQUIRE("avx512bw");
#endif
#ifdef __AVX512DQ__
  CAPFLOW_REQUIRE("avx512dq");
#endif
}

#undef CAPFLOW_REQUIRE

}  // namespace
