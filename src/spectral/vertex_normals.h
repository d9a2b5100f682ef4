#pragma once
// Area-weighted vertex normals on flat float arrays: the shading normals of a view (the viewport's per-frame path,
// and a display level's rest-shape normals, computed once with the level: display_level.h).

#include <cstdint>
#include <span>

namespace sc::spectral {

/// Area-weighted vertex normals: each vertex gets the normalised sum of the (unnormalised) cross products
/// (v1 - v0) × (v2 - v0) of its incident faces, i.e. face normals weighted by twice the face area.
/// @param[in]  xyz      3·#V floats, x y z per vertex.
/// @param[in]  indices  3·#F vertex indices in [0, #V), counter-clockwise per face (seen from outside: outward
///                      normals). Asserted, not checked, in release builds.
/// @param[out] normals  3·#V floats (same size as xyz), overwritten with unit normals; a vertex with no incident
///                      face, or whose incident faces cancel or have zero area, gets the zero vector.
/// Cost: O(#V + #F), no allocation.
void vertexNormals(std::span<const float> xyz, std::span<const std::uint32_t> indices, std::span<float> normals);

}  // namespace sc::spectral
