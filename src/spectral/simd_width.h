// capflow/spectral/simd_width: how many doubles the hot kernels' vector blocks hold on this CPU.
// The kernels are templates on that width (stokes/lagrange_line.h) with load-time clones per
// instruction set (target_clones.h), and each clone is fast only at its own width: 8 (one 512-bit
// register) in the x86-64-v4 clones (AVX-512), 4 in the x86-64-v3 ones (AVX2), 2 (SSE) or the
// build's own width in the baseline. Wider blocks than the registers spill to the stack (the
// AVX2 clones of the 8-wide kernels were ~5.6x slower, docs/performance.md "Instruction set").
// Every width adds the same numbers in the same order: within one clone the results have the same
// bits at every width (the clones themselves may differ in rounding: the baseline has no FMA).
#pragma once

namespace capflow::spectral {

// The widest block of the clones this CPU runs (8, 4 or 2), within limit_simd_width's limit.
int simd_width();

// simd_width with its instruction set, for logs: "AVX-512, 8 doubles", "AVX2, 4 doubles" or
// "SSE2, 2 doubles".
const char* simd_width_name();

// Caps simd_width at w (8, 4 or 2; anything else throws std::invalid_argument): for tests and
// benchmarks of the narrower kernels on a wider CPU. Not for use while kernels run.
void limit_simd_width(int w);

}  // namespace capflow::spectral
