#pragma once
// Private to src/spectral (reconstruction_kernel.cpp): the x86-64 AVX2 + FMA loop of X' = X̂' + K·Z, chosen at run
// time when the CPU has both (compiled with function target attributes, so it does not need -march=native).
//
// Loop: four rows of K per pass. For each 8-column chunk the three coordinates' 8 values of Z sit in 3 ymm registers
// and serve the 4 rows: 4 loads of K (int16 → int32 → float, or float), 12 FMAs into 12 accumulators (4 rows × xyz);
// at the end of the 4 rows the 12 accumulators are summed horizontally together (9 vhaddps, 3 lane moves, 2 adds)
// into the 12 contiguous output floats. Columns past the last multiple of 8 are one more chunk: the row's last 8
// entries (loaded in bounds) against a copy of Z whose lanes already counted are zero, so K is never read past a row
// and there is no scalar tail. Rows left over by a thread's range (count mod 4), and every row when m < 8, go through
// a zero-padded 4-row copy: the arithmetic of a row does not depend on where it falls, so any split into threads
// gives bit-identical buffers.

#include <Eigen/Core>

#include <cstdint>

namespace sc::spectral::detail {

/// Whether this CPU runs reconstructAvx2 (AVX2 and FMA, checked once); always false off x86-64.
[[nodiscard]] bool avx2KernelAvailable();

/// out[3i + c] = rest[3i + c] + Σ_j K(i, j)·Z(j, c) for every row i of K, rows split over `threads` (parallelRanges).
/// @param[in] K  n by m row-major, n·m entries. @param[in] Z  m by 3. @param[in] rest, out  3·n floats, not aliased.
/// Requires avx2KernelAvailable(). Cost: 6·n·m flops, one read of K, ≈ 24·⌈m/8⌉ floats of Z laid out per call.
void reconstructAvx2(const float* K, Eigen::Index n, Eigen::Index m, const float* rest, const Eigen::MatrixXf& Z,
                     float* out, int threads);
void reconstructAvx2(const std::int16_t* K, Eigen::Index n, Eigen::Index m, const float* rest, const Eigen::MatrixXf& Z,
                     float* out, int threads);

}  // namespace sc::spectral::detail
