#pragma once
// Coarse levels of the generalized eigenproblem S h = λ M h by smoothed vertex aggregation (Galerkin coarsening).

#include "spectral/laplace_operators.h"

#include <Eigen/Core>

#include <vector>

namespace sc::spectral {

/// One coarsening step: aggregates of the finer level's vertices, the smoothed prolongation and the Galerkin
/// operators on the aggregates.
struct AggregatedOperators {
  /// S_c = PᵀSP (#A by #A, symmetric PSD, S_c·1 = 0) and mass_c = Pᵀmass (> 0, same total area): the fine problem
  /// restricted to the span of P, with the mass lumped (row sums of PᵀMP, exact because P·1 = 1).
  LaplaceOperators coarse;
  /// P (#V by #A): the piecewise-constant prolongation P₀ (P₀_ia = 1 when vertex i is in aggregate a) after one
  /// damped-Jacobi smoothing with S, P = (I − ω D⁻¹S) P₀, D = diag(S). P·1 = 1 (S·1 = 0) and a column only touches
  /// vertices of its aggregate's connected component.
  SparseMatrix prolongation;
  Eigen::VectorXi aggregate;  ///< #V aggregate index of every finer vertex, in [0, #A).
  Eigen::Index coarseSize() const { return coarse.mass.size(); }
};

/// The levels below `ops`, finest first (levels[0] coarsens ops, levels[k] coarsens levels[k − 1].coarse), as long
/// as a step leaves at least `minVertices` aggregates and merges something; empty when no step can.
///
/// One step is greedy graph aggregation on the pattern of S (as in smoothed-aggregation multigrid): every vertex not
/// yet taken, in index order, becomes a seed and takes its untaken neighbours; leftovers join a neighbouring
/// aggregate. On a triangle mesh the first step divides the vertex count by about 5–7; later steps, on the wider
/// stencil of S_c, by more. Aggregates never span two connected components (they follow the edges of S), so S_c has
/// exactly as many zero eigenvalues as S.
/// Why smoothed: the Galerkin operators of piecewise-constant P₀ overrate the energy of smooth functions (the jumps
/// between aggregates), so their eigenpairs are poor starts; the smoothed columns are hat-like functions (a coarse
/// linear finite-element space), whose Galerkin eigenpairs approximate the low spectrum to O(h²).
/// ω = (4/3)/ρ with ρ ≥ ρ(D⁻¹S) the Gershgorin bound (2 for a Laplacian with non-positive off-diagonal).
/// @param[in] ops  fine operators (S symmetric PSD with the mesh's edge pattern, S·1 = 0, mass > 0).
/// Cost: O(nnz(S)) per step plus the sparse product PᵀSP; memory O(nnz(S) + nnz(P)).
std::vector<AggregatedOperators> aggregationHierarchy(const LaplaceOperators& ops, Eigen::Index minVertices);

}  // namespace sc::spectral
