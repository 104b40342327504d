// capflow/app/cpu_budget: how the solver and the renderer share the cores (Milestone 13).
//
// The solver's OpenMP team spins at its barriers; when the renderer thread (and llvmpipe's
// rasteriser threads) run beside a full team, both fight over the cores and each parallel region
// waits for its descheduled thread. The policy:
//  * while a movie frame is queued or being rendered (RenderThread's busy signal), the solver's
//    boundary operators run with one thread fewer (at least one; stokes::set_thread_cap, read
//    by each operator call, so the change takes effect within a fraction of a millisecond): the
//    renderer gets a core of its own;
//  * otherwise the cap is off and the solver uses every thread it was given (numerics.threads;
//    0: OpenMP's default), so the renderer never holds a core when no frame is pending;
//  * the solver threads the cap leaves idle wait in OpenMP's dock, spinning for a few
//    milliseconds (GOMP_SPINCOUNT) before they sleep; while a frame is pending they run at nice
//    19 (set by the solver's first operator call under the cap, when they are idle), so that
//    their spinning takes little of the renderer's core, and at their own nice value again once
//    it is written. Lowering the nice value back needs root, CAP_SYS_NICE or
//    RLIMIT_NICE: without them the threads are left as they are;
//  * the renderer works on one core: llvmpipe gets one rasteriser thread (LP_NUM_THREADS=1,
//    unless the user set it; other drivers ignore it), which runs while the render thread waits
//    for it.
// The knobs: numerics.threads (the solver's threads), LP_NUM_THREADS (llvmpipe's), and
// OMP_WAIT_POLICY (passive waits cost the solver ~10 % without frames here, so it is left to the
// user).
#pragma once

#include <string>

namespace capflow::app {

// numerics.threads (at the start and on live edits): the solver's OpenMP threads when > 0
// (0: OpenMP's default, OMP_NUM_THREADS or all cores); remembered for the cap. The count is
// capped by what the process may create: libgomp ends the process when it cannot start a thread,
// so a count above any used before is first tried with real threads (creatable_threads), and a
// smaller one (half of what could be started: the limit is on processes or memory, which the
// buffers and the renderer share) is used when they cannot all be made. Returns the count set; *warning (when given)
// says why it is below the one asked for ("" when it is not).
int set_solver_threads(int threads, std::string* warning = nullptr);

// How many threads (this one included) the process can run at once, up to `wanted`: threads are
// started with the default attributes (the stack size libgomp uses) until one cannot be, then
// all of them end. `wanted` when every one started.
int creatable_threads(int wanted);

// Starts the solver's OpenMP threads and makes their operator buffers now, before the renderer
// loads its GL driver: a thread's first operator call would otherwise register its buffers'
// destructors under the loader lock that the driver's dlopen holds (stokes/thread_buffers.h).
// Records the team's threads for renderer_busy; true when their nice values can be raised
// while a frame is pending and lowered back after it (root, CAP_SYS_NICE or RLIMIT_NICE).
bool start_solver_threads();

// The renderers' busy callback (RenderThread's, the live console's FrameService): caps the
// solver's operators at one thread fewer while any of them is busy (calls come in pairs: true,
// then false). Thread-safe.
void renderer_busy(bool busy);

// The renderer's one-core default, set in the environment before its GL context exists:
// LP_NUM_THREADS=1 unless already set (true when this call set it).
bool render_cpu_defaults();

}  // namespace capflow::app
