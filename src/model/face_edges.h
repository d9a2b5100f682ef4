#pragma once
// Internal to src/model (no OpenMesh, no meshoptimizer): the directed edges of a triangle list by source vertex,
// and what decimation reads from them: the faces a halfedge mesh would refuse, and the nearest surviving vertex.

#include <Eigen/Core>

#include <array>
#include <vector>

namespace sc::model::detail {

/// The directed edges a→b of the triangles (a, b, c) → (a→b, b→c, c→a), grouped by source vertex (CSR), each group
/// in face order. Vertices referenced by no face have empty groups.
struct OutgoingEdges {
  std::vector<int> offsets;  ///< #V + 1: the edges leaving v are [offsets[v], offsets[v + 1]).
  std::vector<int> targets;  ///< 3·#F: the vertex each edge points to.
  std::vector<int> faces;    ///< 3·#F: the face each edge comes from.
};

/// Builds the directed edges. @param[in] F  #F by 3 indices in [0, vertexCount). Cost: O(#V + #F), 24·#F bytes.
OutgoingEdges outgoingEdges(Eigen::Index vertexCount, const Eigen::MatrixXi& F);

/// The faces a halfedge mesh (OpenMesh's add_face(), faces added in order) would refuse on their edges: a face is
/// refused when it repeats a corner, or when one of its directed edges is already used by an accepted earlier face
/// (a third face on an edge, or a neighbour of the opposite orientation). OpenMesh also refuses faces that would
/// join two fans at one vertex ("complex vertex"); those are accepted here (meshoptimizer locks such vertices).
/// @return #F flags, 1 for a refused face. Cost: O(#F · vertex degree).
std::vector<char> refusedFaces(const Eigen::MatrixXi& F, const OutgoingEdges& edges);

/// Each corner of `faces` moved to a `kept` vertex (flags per vertex): itself when kept; else the nearest kept
/// vertex in edges of faces not `refused` (breadth-first along outgoing edges), preferring among the equally near
/// one that no other corner of the face stands for (a corner is taken to have collapsed onto a vertex its face
/// already uses only when nothing else is as near); itself when it reaches no kept vertex. Stands in for the
/// collapse chains a simplifier does not report. Degenerate results are the caller's to drop.
/// Cost: O(#V) to allocate, then O(vertices visited), about #V / #kept per moved corner.
std::vector<std::array<int, 3>> movedToKept(const std::vector<std::array<int, 3>>& faces, const std::vector<char>& kept,
                                            const OutgoingEdges& edges, const std::vector<char>& refused);

}  // namespace sc::model::detail
