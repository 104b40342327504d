// capflow/stokes/kernel_mode: which kernel sum an application of the boundary operators
// computes (boundary_integral.h): the single layer SL[f], INT S.n dS, the double layer DL[u], or
// INT T.n dS (3 x 3 per target), or the double layer as a matrix (stokes/matrix_sums.h).
#pragma once

namespace capflow::stokes {

enum class Mode { Single, SingleNormal, Double, DoubleNormal, DoubleMatrix };

// The modes with a nodal density (f or u).
constexpr bool uses_density(Mode m) {
  return m == Mode::Single || m == Mode::Double;
}

}  // namespace capflow::stokes
