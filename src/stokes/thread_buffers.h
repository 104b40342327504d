// capflow/stokes/thread_buffers: each thread's working memory of the boundary operators, kept
// across calls (thread_local, one set per kernel mode). Allocated per call, the far data (0.3 +
// 0.5 MB at NB=10) and the line buffers made glibc grow and trim its heap on every call, ~200
// page faults a call (docs/performance.md, "Heap churn").
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "stokes/far_field.h"
#include "stokes/kernel_mode.h"
#include "stokes/line_sums.h"
#include "stokes/matrix_sums.h"
#include "stokes/own_lines.h"

namespace capflow::stokes {

// far_data's temporaries for one Gauss order nq: one element's nodal copy X of a coordinate or
// density row, the half-interpolated products XI = X I^T and IX = I X, and the coordinates'
// derivatives at the Gauss points (the positions and the density go straight into F.d).
struct FarWorkspace {
  int nq = 0;  // the order they are sized for (0: not yet used)
  Eigen::MatrixXd X, XI, IX, xsq[3], xtq[3];
};

struct ThreadBuffers {
  FarData far[3];                    // a call's far data by tier: the calling thread's, shared with
                                     // its team
  std::vector<ChebElement> cheb;     // single layer: the elements in Chebyshev coefficients
  OwnLines own_lines;                // single layer: a call's own lines after stage 1
  Scratch scratch;                   // a team thread's element data and line buffers
  std::vector<FarWorkspace> far_ws;  // a team thread's far_data temporaries, one per Gauss order
  MatrixWorkspace matrix;            // a team thread's matrix sums (the assembled double layer)
};

// b's far_data temporaries for Gauss order nq (made on first use; valid until the next call): one
// set per order, so that the tiers of a call (up to three orders) do not resize each other's
// (which cost ~100 us of reallocation and page faults at the first element of every tier,
// docs/performance.md "Heap churn").
FarWorkspace& far_workspace(ThreadBuffers& b, int nq);

// The calling thread's buffers of mode M.
template <Mode M>
ThreadBuffers& thread_buffers();

// Makes the buffers of the calling thread and of the other threads of its OpenMP team of `team`
// threads now. A thread-local object's first use registers its destructor under glibc's loader
// lock (__cxa_thread_atexit_impl takes dl_load_lock), which a dlopen in another thread holds
// for the whole relocation of the library: the renderer's loading of llvmpipe (libLLVM) stalled
// the solver's first operator call by 60-70 ms. Call before such a dlopen can start.
void prepare_thread_buffers(int team);

}  // namespace capflow::stokes
