// capflow/stokes/thread_cap: a process-wide cap on the threads of the boundary operators'
// parallel regions, which any thread may change at any time (an atomic); each region reads it as
// it starts. 0: no cap (OpenMP's own count, omp_get_max_threads of the calling thread).
// The run's CPU budget (app/cpu_budget.h) lowers it while the renderer draws a frame, so the
// solver's next region (a fraction of a millisecond away) leaves the renderer a core.
#pragma once

namespace capflow::stokes {

void set_thread_cap(int threads);  // threads <= 0: no cap
int thread_cap();
// The team size of an operator's parallel region: omp_get_max_threads(), at most the cap.
int team_size();

}  // namespace capflow::stokes
