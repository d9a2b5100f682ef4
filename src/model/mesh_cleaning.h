#pragma once
// Cleaning of triangle soups into meshes the spectral operators accept.

#include <Eigen/Core>

namespace sc::model {

/// What cleanMesh() changed (counts of removed items) and what it found (diagnostics it leaves in place).
struct MeshCleanReport {
  int mergedDuplicateVertices = 0;      ///< vertices merged into an earlier one at exactly the same position.
  int droppedRepeatedIndexFaces = 0;    ///< faces that named one vertex twice (after merging).
  int droppedZeroAreaFaces = 0;         ///< faces whose area is zero to round-off (collinear corners).
  int droppedDuplicateFaces = 0;        ///< faces over the same three vertices as an earlier face.
  int droppedUnreferencedVertices = 0;  ///< vertices no remaining face uses.
  int nonManifoldEdges = 0;             ///< edges shared by more than two faces (kept).
  int boundaryLoops = 0;                ///< closed loops of boundary edges, i.e. holes (kept).
  int components = 0;                   ///< connected components of the cleaned mesh.
};

/// Cleans a triangle soup in place, in this order: merge exactly coincident vertices (−0 equals +0), drop
/// faces with a repeated index, drop zero-area faces, drop duplicate faces (the same three vertices in any order or
/// orientation; the first is kept), drop unreferenced vertices (re-indexing F); then counts non-manifold edges,
/// boundary loops and components. Kept vertices and faces stay in their original relative order; a mesh with
/// nothing to clean comes back bit-identical.
///
/// A face has zero area when ‖(b−a)×(c−a)‖ ≤ 64·ε·ℓ², ℓ its longest edge and ε the double epsilon: exactly
/// collinear corners up to rounding. A boundary loop is a connected set of boundary edges (edges with one face),
/// so two holes that touch at a vertex count as one loop.
/// @param[in,out] V  #V by 3 positions; rows removed.
/// @param[in,out] F  #F by 3 indices into V; rows removed and re-indexed.
/// @pre every index in F lies in [0, #V) (asserted in debug builds; loadMesh() guarantees it).
/// @return the report.
/// Cost: O(#V log #V + #F log #F) time, O(#V + #F) extra memory.
MeshCleanReport cleanMesh(Eigen::MatrixXd& V, Eigen::MatrixXi& F);

}  // namespace sc::model
