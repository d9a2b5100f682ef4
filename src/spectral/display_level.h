#pragma once
// The one-way frame path's two values (docs/architecture.md, "The frame path"):
//   - DisplayLevel: what a peer draws at one resolution, immutable once built and shared by pointer
//     (std::shared_ptr<const DisplayLevel>) between the session that built it and every view that shows it, so a
//     process holds one int16 K (QuantizedBasis) per displayed level (a host also keeps the double H its deformer
//     needs);
//   - DisplayFrame: the current frame, a frame number and Z (m by 3, float32), a small value copied freely.
// Positions are X̂' + K·Z, computed by reconstruct() (the CPU kernel, reconstruction_kernel.h) or by the viewport's
// vertex shader: the only two places that formula is written.

#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace sc::spectral {

struct DisplayLevel {
  ResolutionLevel level;    ///< X̂' (restV, n' by 3), F', P (n' by n) and K (n' by m, int16 with a scale per column)
  std::vector<float> rest;  ///< X̂' interleaved, 3·n' floats (the kernel's and the vertex buffer's layout)

  [[nodiscard]] std::uint32_t vertexCount() const { return static_cast<std::uint32_t>(level.restV.rows()); }
  [[nodiscard]] int basisSize() const { return static_cast<int>(level.K.cols()); }
};

using SharedDisplayLevel = std::shared_ptr<const DisplayLevel>;

/// Wraps a level for display: moves it in and computes its interleaved rest positions once. Cost: O(n').
[[nodiscard]] SharedDisplayLevel makeDisplayLevel(ResolutionLevel level);

struct DisplayFrame {
  std::uint32_t frame = 0;  ///< the session's frame number (0: the rest shape, before any frame)
  Eigen::MatrixXf Z;        ///< m by 3 coefficients; an empty matrix stands for zero (the rest shape)
};

/// out = X̂' + K·Z for `level` and `frame` (the rest positions when frame.Z is empty). out.size() == 3·n'.
/// Cost: reconstructInterleaved(): 6·n'·m flops and one read of K (docs/benchmarks.md has the measured time).
void reconstruct(const DisplayLevel& level, const DisplayFrame& frame, std::span<float> out, int threads = 1);

/// The same into a new buffer. Cost: as reconstruct() plus one allocation of 3·n' floats.
[[nodiscard]] std::vector<float> reconstructed(const DisplayLevel& level, const DisplayFrame& frame, int threads = 1);

}  // namespace sc::spectral
