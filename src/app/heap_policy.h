// capflow/app/heap_policy: how the process returns freed heap memory to the system.
//
// glibc gives the top of a heap back (brk / madvise) whenever more than M_TRIM_THRESHOLD
// (128 KiB, adapted upwards only by mmap-sized frees) is free there. A time step frees its
// temporaries (the stages, the smoothing's and the diagnostics' work arrays) at its end, so the
// heap shrank and regrew every step: page faults on the regrowth, and each shrink flushes the
// TLB of every core running the process (an interprocessor interrupt to the OpenMP threads).
// keep_freed_heap() raises the threshold to 64 MiB: memory freed during a run stays with the
// process (the peak use is unchanged to 0.3 MiB) and runs are 3-8 % faster.
// Setting the trim threshold switches off glibc's adaptive mmap threshold, so every block of
// 128 KiB or more (the viscosity-ratio solve's double-layer matrix, 0.35 MB at NE=6 NB=10) was
// mapped and unmapped afresh at each use, page faults again: keep_freed_heap() also sets
// M_MMAP_THRESHOLD to its largest value, 32 MiB, so such blocks come from the heap and are reused
// (a lambda = 5 run in 0.84x the time, lambda = 1 unchanged; docs/performance.md, "The heap between
// steps"). Thresholds the user set (MALLOC_TRIM_THRESHOLD_, MALLOC_MMAP_THRESHOLD_ or
// GLIBC_TUNABLES glibc.malloc.trim_threshold / mmap_threshold) are left as they are.
#pragma once

namespace capflow::app {

// Returns false when the environment sets a threshold (that one unchanged) or mallopt fails.
bool keep_freed_heap();

}  // namespace capflow::app
