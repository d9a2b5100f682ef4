#pragma once
// Per-vertex normals for shading, computed on the CPU from (V, F).

#include "spectral/vertex_normals.h"

#include <Eigen/Core>

namespace sc::app {

/// Area-weighted vertex normals: each vertex gets the normalised sum of the (unnormalised) cross products
/// (v1 - v0) × (v2 - v0) of its incident faces, i.e. face normals weighted by twice the face area.
/// @param[in] V  #V by 3 positions.
/// @param[in] F  #F by 3 indices into V; a counter-clockwise face (seen from outside) gives outward normals.
/// @return #V by 3 unit normals. A vertex with no incident face, or whose incident faces cancel or have zero
///         area, gets the zero vector (callers that normalise must guard against it).
/// \note Indices must lie in [0, #V); this is asserted, not checked, in release builds.
/// Cost: O(#V + #F).
Eigen::MatrixXd vertexNormals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// The same normals in float on flat arrays (the viewport's per-frame path): spectral::vertexNormals().
using spectral::vertexNormals;

}  // namespace sc::app
