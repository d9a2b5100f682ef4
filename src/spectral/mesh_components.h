#pragma once
// Connected components of a triangle mesh's vertex graph.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sc::spectral {

/// Labels the connected components of the graph whose edges are the triangles' edges (union–find).
///
/// @param[in] vertexCount  #V; vertices referenced by no face form components of their own.
/// @param[in] F  #F by 3 vertex indices in [0, vertexCount).
/// @param[out] labels  #V component index per vertex, numbered 0.. in order of each component's first vertex.
/// @return the number of components.
/// Cost: O(#V + #F·α(#V)).
int connectedComponents(Eigen::Index vertexCount, const Eigen::MatrixXi& F, Eigen::VectorXi& labels);

/// Labels the connected components of the graph of a sparse matrix's pattern (i ~ j when A_ij is stored), e.g.
/// the stiffness matrix S of a mesh. Same numbering rule as above. Cost: O(n + nnz·α(n)).
int connectedComponents(const Eigen::SparseMatrix<double>& pattern, Eigen::VectorXi& labels);

}  // namespace sc::spectral
