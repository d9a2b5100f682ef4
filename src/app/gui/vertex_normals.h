#pragma once
// Per-vertex normals for shading, computed on the CPU from (V, F).

#include <Eigen/Core>

#include <cstdint>
#include <span>

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

/// The same area-weighted normals in float, on flat arrays: the per-frame path of MeshViewport, which avoids any
/// Eigen matrix conversion.
/// @param[in]  xyz      3·#V floats, x y z per vertex.
/// @param[in]  indices  3·#F vertex indices in [0, #V), counter-clockwise per face.
/// @param[out] normals  3·#V floats (same size as xyz), overwritten with unit normals or zero (as above).
/// Cost: O(#V + #F), no allocation.
void vertexNormals(std::span<const float> xyz, std::span<const std::uint32_t> indices, std::span<float> normals);

}  // namespace sc::app
