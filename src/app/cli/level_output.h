#pragma once
// `shapecast-cli deform --level N`: the deformed mesh at a lower display resolution, reconstructed as a client
// would (README "Low-resolution clients", src/spectral/resolution_level.h): decimated rest mesh X̂', barycentric map
// P, K = P·H, and per frame X' = X̂' + K·Z with the float32 kernel.

#include "spectral/resolution_level.h"

#include <Eigen/Core>
#include <QJsonObject>

#include <optional>
#include <vector>

namespace sc::app {

/// The vertex count asked for by --level N on a mesh of `vertexCount` vertices: N = 1, 2, 3 are the default ladder
/// (model::levelTargets(): 50 %, 20 %, 5 %), any N > 3 an explicit count; N = 0 (full resolution) gives nullopt.
/// \pre level ≥ 0.
std::optional<int> levelVertexTarget(int level, int vertexCount);

/// One display level of a full-resolution mesh, and the client-side reconstruction of the frames replayed on it.
///
/// Usage: construct (decimates and builds P and K), call frame() with each frame's Z, then read positions() (the
/// last frame) and report().
class LevelOutput {
 public:
  /// Decimates (V, F) to `targetVertices` (model::decimateMesh) and builds the level (spectral::resolutionLevel).
  /// @param[in] V, F  full-resolution rest mesh; @param[in] H  its n by m basis.
  /// @param[in] level  the --level value, for the report. Cost: one decimation plus resolutionLevel().
  LevelOutput(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H, int level,
              int targetVertices);

  /// Reconstructs one frame, X' = X̂' + K·float(Z) (spectral::reconstructInterleaved, one thread), and records the
  /// time of the kernel call alone (the conversion of Z to float32 is not timed: a client receives it as floats).
  /// @param[in] Z  m by 3 coefficients of the frame.
  void frame(const Eigen::MatrixXd& Z);

  /// n' by 3 positions of the last frame() (the rest X̂' before any frame).
  Eigen::MatrixXd positions() const;

  /// The low-res faces, indices into positions().
  const Eigen::MatrixXi& faces() const { return m_level.F; }

  /// Report keys `level, level_vertices, level_triangles, level_build_s, client_frame_us` (median over the frames;
  /// 0 without frames) and `hausdorff_pct`: spectral::hausdorffDistance() between positions() and P·X, in % of
  /// `diagonal`.
  /// @param[in] X  the full-resolution result of the same last frame (n by 3).
  /// @param[in] diagonal  the rest full-resolution bounding-box diagonal.
  QJsonObject report(const Eigen::MatrixXd& X, double diagonal) const;

 private:
  int m_levelArgument = 0;
  spectral::ResolutionLevel m_level;
  double m_buildSeconds = 0.0;
  std::vector<float> m_rest;  ///< X̂' interleaved.
  std::vector<float> m_out;   ///< X' of the last frame, interleaved.
  Eigen::MatrixXf m_Z;        ///< float copy of the frame's Z (reused).
  std::vector<double> m_frameUs;
};

}  // namespace sc::app
