#pragma once
// The client's per-frame hot path at a display resolution: X' = X̂' + K·Z in float32, written straight into an
// interleaved xyz vertex buffer (shared/design/spectral.md §6, "Low-resolution clients").
//
// Layout choice: K is row-major (RowMatrixXf), Z column-major. Each output vertex i is three dot products of
// row i of K (m contiguous floats) with the three contiguous columns of Z; Z (m·3 floats, 1.2 kB at m = 100)
// stays in L1, so one frame is a single sequential read of K (4·n'·m bytes, 40 MB at n' = 100k, m = 100) and
// one sequential write of the output. The loop is memory-bound; at 100k × 100 it streams ≈ 10 GB/s per ms budget
// of 4 ms, so the arithmetic (16-lane partial sums, vectorised by the compiler) is not the limit.
// A level's K is int16 with a scale per column (QuantizedBasis): the scales are folded into Z once per frame and the
// inner loop converts int16 to float and multiplies-adds, so a frame reads 2·n'·m bytes (20 MB at 100k × 100).

#include "spectral/quantized_basis.h"
#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace sc::spectral {

/// Positions as an interleaved float buffer x0 y0 z0 x1 y1 z1 … (the layout of an OpenGL vertex buffer).
/// @param[in] V  #V by 3 positions. @return 3·#V floats. Cost: O(#V).
std::vector<float> interleavedPositions(const Eigen::MatrixXd& V);

/// Computes out = X̂' + K·Z, one row of K at a time, all three coordinates in the same pass.
///
/// @param[in] K  n' by m reduced basis (row-major float32), e.g. ResolutionLevel::K.
/// @param[in] rest  3·n' floats, the rest positions X̂' interleaved (interleavedPositions(level.restV)).
/// @param[in] Z  m by 3 displacement coefficients (float32, column-major: each coordinate contiguous).
/// @param[out] out  3·n' floats, interleaved xyz; may not alias `rest`. Written, never read.
/// @param[in] threads  ≥ 1; rows are split into `threads` contiguous chunks, one std::thread each (the caller's
///            thread takes the first). Threads are started per call (≈ 20–50 µs each), so use > 1 only for large n'.
/// \note Sums in float32 with 16 partial sums per coordinate: relative error ≈ 1e-6 of Σ|K_ik Z_kc|.
/// Cost: 6·n'·m flops and 4·n'·m bytes read (memory-bound); about 2.5 ms at n' = 100k, m = 100 on one core of
///       the development machine (bench/kernel_bench.cpp, docs/benchmarks.md).
void reconstructInterleaved(const RowMatrixXf& K, std::span<const float> rest, const Eigen::MatrixXf& Z,
                            std::span<float> out, int threads = 1);

/// The same with a quantised K (a level's): out = X̂' + Q·(scale ⊙ Z), i.e. X̂' + dequantized(K)·Z up to float
/// rounding. Same contract as above. Cost: one m by 3 product for the scaled Z, then 6·n'·m flops and 2·n'·m bytes
/// read (memory-bound); docs/benchmarks.md has the measured time at 100k × 100.
void reconstructInterleaved(const QuantizedBasis& K, std::span<const float> rest, const Eigen::MatrixXf& Z,
                            std::span<float> out, int threads = 1);

}  // namespace sc::spectral
