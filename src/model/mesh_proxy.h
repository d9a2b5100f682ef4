#pragma once
// Interactive proxies: a coarse triangulation of a dense mesh's own vertices, which a viewport draws instead of
// the mesh while the shape moves (src/app/gui/interactive_proxy.h).

#include <Eigen/Core>

namespace sc::model {

/// A coarse triangulation of a mesh's own vertices, for drawing a dense mesh cheaply (e.g. while it moves):
/// decimateToTriangles(V, F, targetTriangles)'s faces named by input vertex (DecimatedMesh::sourceVertices).
/// Collapses keep the surviving vertices in place, so the proxy follows every deformation of V (same vertex
/// buffer); non-manifold faces are carried through the collapses, so they leave no holes.
/// @param[in] V  #V by 3 positions.
/// @param[in] F  #F by 3 indices into V.
/// @param[in] targetTriangles  ≥ 1; the proxy has about this many triangles (a few more on a mesh with refused
///            faces), or is F itself (copied) when F has no more than that.
/// @return #F' by 3 indices into V, orientation as in the input.
/// Cost: that of decimateToTriangles() (one meshopt_simplify run: about 0.7 s for the 437k dragon, 0.15 s for the
/// 100k one, on 2 loaded cores).
Eigen::MatrixXi proxyTriangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetTriangles);

}  // namespace sc::model
