// capflow/spectral/target_clones: CAPFLOW_TARGET_CLONES(...) compiles a hot function once per
// listed architecture, chosen at load time by an ifunc resolver (GCC target_clones). Empty
// under CAPFLOW_NO_TARGET_CLONES, which ThreadSanitizer builds set: the resolver runs during
// relocation, before the TSan runtime is up, and crashes there. CAPFLOW_CLONES_UP_TO_V3
// (-DCAPFLOW_CLONES_UP_TO_V3=ON, with -DCAPFLOW_ARCH_FLAGS=-march=x86-64-v2) keeps only the
// x86-64-v3 and baseline clones, to measure the AVX2 kernels on an AVX-512 machine
// (simd_width.h then reports the AVX2 clones' width).
#pragma once

#if defined(CAPFLOW_NO_TARGET_CLONES)
#define CAPFLOW_TARGET_CLONES(...)
#elif defined(CAPFLOW_CLONES_UP_TO_V3)
#define CAPFLOW_TARGET_CLONES(...) __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CAPFLOW_TARGET_CLONES(...) __attribute__((target_clones(__VA_ARGS__)))
#endif
