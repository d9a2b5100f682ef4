#pragma once
// Point-to-surface distances between meshes (the MeshLab "Hausdorff Distance" metric, shared/design/spectral.md §7):
// every vertex of one mesh to the exact closest point on the other mesh's triangles. The normalising diagonal
// comes from boundingBoxDiagonal() (hausdorff.h, with the vertex-set metric).

#include "spectral/hausdorff.h"

#include <Eigen/Core>

namespace sc::spectral {

/// Max, mean and root-mean-square of a set of distances.
struct DistanceStats {
  double max{};
  double mean{};
  double rms{};
};

/// One-sided vertex-to-surface distances, raw (mesh units) and divided by a reference bbox diagonal.
struct SurfaceDistance {
  DistanceStats raw;
  DistanceStats relative;  ///< raw / diagonal (× 100 for percent).
};

/// Both directions and their symmetric maximum (the symmetric point-to-surface Hausdorff estimate).
struct SymmetricSurfaceDistance {
  SurfaceDistance aToB;  ///< vertices of A to the surface of B.
  SurfaceDistance bToA;  ///< vertices of B to the surface of A.
  double maxRaw{};       ///< max(aToB.raw.max, bToA.raw.max).
  double maxRelative{};  ///< maxRaw / diagonal.
};

/// One-sided distances from every point to the surface (V, F).
/// @param[in] points  #P by 3 samples (e.g. the vertices of the measured mesh), #P ≥ 1.
/// @param[in] V, F  target triangle mesh, #F ≥ 1.
/// @param[in] diagonal  > 0, normalisation length; spectral.md §7 fixes it to the rest high-res bbox diagonal.
/// @param[in] threads  threads for the closest-point queries.
/// \note Vertices only (MeshLab's default sampling), no MaxDist cut-off.
/// Cost: O(#F log #F) AABB tree build plus O(#P log #F) queries.
SurfaceDistance pointToSurfaceDistance(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                       const Eigen::MatrixXi& F, double diagonal, int threads = 1);

/// pointToSurfaceDistance() in both directions between meshes A and B, and the max of both.
/// Cost: two tree builds and #VA + #VB queries.
SymmetricSurfaceDistance symmetricSurfaceDistance(const Eigen::MatrixXd& VA, const Eigen::MatrixXi& FA,
                                                  const Eigen::MatrixXd& VB, const Eigen::MatrixXi& FB, double diagonal,
                                                  int threads = 1);

}  // namespace sc::spectral
