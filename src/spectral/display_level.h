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

/// What a view needs to draw a level besides X̂' and K, computed once with the level by makeDisplayLevel(), on the
/// thread that builds or decodes it, so that the thread that shows it only swaps the shared level in and uploads
/// (issue 19 item 3: at a million vertices these arrays took the client's GUI thread about 0.2 s per level).
struct DisplayGeometry {
  Eigen::RowVector3d origin = Eigen::RowVector3d::Zero();  ///< centre of X̂''s bounding box
  std::vector<float> rest;             ///< X̂' − origin interleaved, 3·n' floats (float precision on the shape)
  std::vector<float> normals;          ///< area-weighted unit normals of `rest` over F' (vertexNormals()), 3·n'
  std::vector<std::uint32_t> indices;  ///< F' row by row, 3·f' (an element buffer)
  Eigen::Vector3f lo = Eigen::Vector3f::Zero();  ///< bounding box of `rest` (zero for n' = 0)
  Eigen::Vector3f hi = Eigen::Vector3f::Zero();
  float maxRowNorm = 0.0f;          ///< max_i ‖K_i‖ of the dequantised K (0 without K)
  Eigen::RowVectorXf maxAbsColumn;  ///< 1 by m: max_i |K_ik| of each dequantised column
};

struct DisplayLevel {
  ResolutionLevel level;     ///< X̂' (restV, n' by 3), F', P (n' by n) and K (n' by m, int16 with a scale per column)
  std::vector<float> rest;   ///< X̂' interleaved, 3·n' floats (the kernel's and the vertex buffer's layout)
  DisplayGeometry geometry;  ///< a view's arrays of this level (no normals when a face index is out of range)

  [[nodiscard]] std::uint32_t vertexCount() const { return static_cast<std::uint32_t>(level.restV.rows()); }
  [[nodiscard]] int basisSize() const { return static_cast<int>(level.K.cols()); }
};

using SharedDisplayLevel = std::shared_ptr<const DisplayLevel>;

/// Wraps a level for display: moves it in and computes its interleaved rest positions and its DisplayGeometry once.
/// Faces with an index outside [0, n') leave the normals at zero (decoded levels are checked before). Cost:
/// O(n'·m + f'), about 0.2 s at n' = 10⁶, m = 100 on one loaded core; memory 12·f' + 24·n' bytes besides the level.
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
