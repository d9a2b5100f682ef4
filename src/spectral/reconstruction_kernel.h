#pragma once
// The client's per-frame hot path at a display resolution: X' = X̂' + K·Z in float32, written straight into an
// interleaved xyz vertex buffer (shared/design/spectral.md §6, "Low-resolution clients").
//
// Layout choice: K is row-major (RowMatrixXf, or QuantizedBasis's int16 Q), Z column-major. Each output vertex i is
// three dot products of row i of K (m contiguous entries) with the three columns of Z; Z (m·3 floats, 1.2 kB at
// m = 100) stays in L1, so one frame is a single sequential read of K and one sequential write of the output.
// A level's K is int16 with a scale per column (QuantizedBasis): the scales are folded into Z once per frame and the
// loop converts int16 to float and multiplies-adds, so a frame reads 2·n'·m bytes (20 MB at 100k × 100).
//
// Two loops, chosen at run time (KernelLoop): on x86-64 CPUs with AVX2 and FMA, four rows per pass so that each
// 8-column chunk of Z, held in 3 registers, serves 4 rows and the horizontal sums are amortised over them
// (reconstruction_kernel_avx2.h); elsewhere a portable loop, one row at a time with 16 partial sums per coordinate,
// vectorised by the compiler. At 100k × 100 int16 the loop is bound by its FMAs (3 per 8 entries), not by the read
// of K: docs/benchmarks.md has the measured times.
#include "spectral/quantized_basis.h"
#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace sc::spectral {

/// Which loop reconstructInterleaved() runs. Fastest: the AVX2 + FMA loop where the CPU has both (checked once at
/// run time), else Portable. Portable: the one-row loop on any CPU (also what tests and the benchmark compare the
/// fast loop with). Both sum in float32; their results differ only by rounding (different summation order).
enum class KernelLoop { Fastest, Portable };

/// The loop `loop` resolves to on this CPU, in words (benchmarks print it).
[[nodiscard]] const char* kernelLoopDescription(KernelLoop loop = KernelLoop::Fastest);

/// Positions as an interleaved float buffer x0 y0 z0 x1 y1 z1 … (the layout of an OpenGL vertex buffer).
/// @param[in] V  #V by 3 positions. @return 3·#V floats. Cost: O(#V).
std::vector<float> interleavedPositions(const Eigen::MatrixXd& V);

/// Computes out = X̂' + K·Z, all three coordinates of a row in the same pass (one or four rows per pass, see above).
///
/// @param[in] K  n' by m reduced basis (row-major float32), e.g. ResolutionLevel::K.
/// @param[in] rest  3·n' floats, the rest positions X̂' interleaved (interleavedPositions(level.restV)).
/// @param[in] Z  m by 3 displacement coefficients (float32, column-major: each coordinate contiguous).
/// @param[out] out  3·n' floats, interleaved xyz; may not alias `rest`. Written, never read.
/// @param[in] threads  ≥ 1; rows are split into `threads` contiguous chunks, one std::thread each (the caller's
///            thread takes the first). Threads are started per call (≈ 20–50 µs each), so use > 1 only for large n'.
/// @param[in] loop  which loop (KernelLoop); a row's result does not depend on `threads` for a given loop.
/// \note Sums in float32 with 8 (AVX2) or 16 (portable) partial sums per coordinate: relative error ≈ 1e-6 of
/// Σ|K_ik Z_kc|.
/// Cost: 6·n'·m flops and 4·n'·m bytes read; docs/benchmarks.md has the measured time at 100k × 100
///       (bench/kernel_bench.cpp).
void reconstructInterleaved(const RowMatrixXf& K, std::span<const float> rest, const Eigen::MatrixXf& Z,
                            std::span<float> out, int threads = 1, KernelLoop loop = KernelLoop::Fastest);

/// The same with a quantised K (a level's): out = X̂' + Q·(scale ⊙ Z), i.e. X̂' + dequantized(K)·Z up to float
/// rounding. Same contract as above. Cost: one m by 3 product for the scaled Z, then 6·n'·m flops and 2·n'·m bytes
/// read (bound by the FMAs with the AVX2 loop); docs/benchmarks.md has the measured time at 100k × 100.
void reconstructInterleaved(const QuantizedBasis& K, std::span<const float> rest, const Eigen::MatrixXf& Z,
                            std::span<float> out, int threads = 1, KernelLoop loop = KernelLoop::Fastest);

}  // namespace sc::spectral
