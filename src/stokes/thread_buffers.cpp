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
  for (FarWorkspace& w : b.far_ws)
    if (w.nq == 0) {
      w.nq = nq;
      return w;
    }
  // more orders than sets (a caller outside the operators' three tiers): the last set is resized
  b.far_ws[2].nq = nq;
  return b.far_ws[2];
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
