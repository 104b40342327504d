// capflow/stokes/thread_cap: a process-wide cap on the threads of the boundary operators'
// parallel regions, which any thread may change at any time (an atomic); each region reads it as
// it starts. 0: no cap (OpenMP's own count, omp_get_max_threads of the calling thread).
// The run's CPU budget (app/cpu_budget.h) lowers it while the renderer draws a frame, so the
// solver's next region (a fraction of a millisecond away) leaves the renderer a core.
#pragma once

namespace capflow::stokes {

void set_thread_cap(int threads);  // threads <= 0: no cap
int thread_cap();
// The team size of an operator's parallel region: omp_get_max_threads(), at most the cap. Called
// by the operator's calling thread before its regions; outside any parallel region it first
// calls the cap observer if the cap changed since the previous such call.
int team_size();

// Called (on the operator's calling thread, between its parallel regions, so the team's other
// threads are idle in OpenMP's dock) with the cap an operator call sees when it differs from the
// one the previous call saw: the place to change how the threads the cap leaves idle wait
// (app/cpu_budget.h). nullptr: none. Set it before the operator calls begin.
void set_cap_observer(void (*observer)(int cap));

}  // namespace capflow::stokes
