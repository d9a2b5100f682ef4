#pragma once
// Internal to src/model: meshoptimizer's edge-collapse simplifier (meshopt_simplify, libmeshoptimizer 0.18) driven
// to a vertex count or a triangle count. No meshoptimizer type in this header.

#include <cstddef>
#include <vector>

namespace sc::model::detail {

/// A triangle list over a fixed vertex array: 3 indices per triangle.
using TriangleIndices = std::vector<unsigned>;

/// Vertices referenced by `indices`. Cost: O(#V + #indices).
std::size_t referencedVertexCount(const TriangleIndices& indices, std::size_t vertexCount);

/// meshopt_simplify to at most `targetTriangles` triangles (it may stop above: topology, e.g. locked non-manifold
/// vertices). Collapses merge a vertex into a neighbour that stays where it is, so the result indexes a subset of
/// the input's vertices; its triangles are the input's in input order, mapped through the collapses, degenerate
/// ones left out. No error limit; no border locking (borders only collapse along themselves).
/// @param[in] positions  3·vertexCount floats (x, y, z per vertex).
/// Cost: O(#indices log #indices + vertexCount) (about 0.15 s for the 100k dragon to 5% on 2 loaded cores).
TriangleIndices simplifyToTriangles(const std::vector<float>& positions, const TriangleIndices& indices,
                                    std::size_t targetTriangles);

/// simplifyToTriangles() steered to about `targetVertices` referenced vertices: a first run on the whole input with
/// a triangle target from its triangles-per-vertex ratio (rerun larger while it lands below), then runs on the
/// (small) result, each aimed proportionally at what is left, until the count is within
/// max(1, targetVertices / 200) of the target or stops moving. Later runs start from the previous result, so they
/// cost little; each reuses nothing of the last one's error quadrics (a small quality cost).
/// Cost: about one simplifyToTriangles() of the input, plus O(#result) per refinement (a handful).
TriangleIndices simplifyToVertices(const std::vector<float>& positions, const TriangleIndices& indices,
                                   std::size_t targetVertices);

}  // namespace sc::model::detail
