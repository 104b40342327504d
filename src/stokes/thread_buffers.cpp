#include "stokes/thread_buffers.h"

#include <omp.h>

#include <algorithm>

namespace capflow::stokes {

template <Mode M>
ThreadBuffers& thread_buffers() {
  thread_local ThreadBuffers b;
  return b;
}

template ThreadBuffers& thread_buffers<Mode::Single>();
template ThreadBuffers& thread_buffers<Mode::SingleNormal>();
template ThreadBuffers& thread_buffers<Mode::Double>();
template ThreadBuffers& thread_buffers<Mode::DoubleNormal>();
template ThreadBuffers& thread_buffers<Mode::DoubleMatrix>();

FarWorkspace& far_workspace(ThreadBuffers& b, int nq) {
  for (FarWorkspace& w : b.far_ws)
    if (w.nq == nq) return w;
  b.far_ws.emplace_back().nq = nq;  // a few orders per process: operators of other NB or orders
  return b.far_ws.back();
}

void prepare_thread_buffers(int team) {
#pragma omp parallel num_threads(std::max(1, team))
  {
    thread_buffers<Mode::Single>();
    thread_buffers<Mode::SingleNormal>();
    thread_buffers<Mode::Double>();
    thread_buffers<Mode::DoubleNormal>();
    thread_buffers<Mode::DoubleMatrix>();
  }
}

}  // namespace capflow::stokes
