#pragma once
// One 1-to-4 midpoint subdivision of a triangle soup: every edge gets a vertex at its midpoint, every triangle
// (a, b, c) becomes (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca). The input vertices keep their indices
// and positions; the new ones follow, one per distinct undirected edge, in order of first appearance. The surface
// is unchanged (only sampled 4× denser), so the large test mesh is a real scan with real detail, not noise.

#include <Eigen/Core>

namespace sc::tools {

struct SubdividedMesh {
  Eigen::MatrixXd V;  ///< (#V + #E) by 3
  Eigen::MatrixXi F;  ///< 4·#F by 3
};

/// @param V  #V by 3.  @param F  #F by 3 indices into V (non-manifold edges allowed: one midpoint per edge).
/// Cost: O(#F log #F) time (edges sorted), O(#F) memory.
SubdividedMesh subdivideMidpoints(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace sc::tools
