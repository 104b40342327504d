// capflow/spectral/target_clones: CAPFLOW_TARGET_CLONES(...) compiles a hot function once per
// listed architecture, chosen at load time by an ifunc resolver (GCC target_clones). Empty
// under CAPFLOW_NO_TARGET_CLONES, which ThreadSanitizer builds set: the resolver runs during
// relocation, before the TSan runtime is up, and crashes there.
#pragma once

#ifdef CAPFLOW_NO_TARGET_CLONES
#define CAPFLOW_TARGET_CLONES(...)
#else
#define CAPFLOW_TARGET_CLONES(...) __attribute__((target_clones(__VA_ARGS__)))
#endif
