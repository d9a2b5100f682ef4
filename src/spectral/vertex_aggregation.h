#pragma once
// A cheap coarse level of the generalized eigenproblem S h = λ M h by vertex aggregation (Galerkin coarsening).

#include "spectral/laplace_operators.h"

#include <Eigen/Core>

namespace sc::spectral {

/// A coarse copy of (S, M) on aggregates of fine vertices, with the piecewise-constant prolongation P (#V by #A,
/// P_ia = 1 when vertex i belongs to aggregate a) stored as the aggregate index of every fine vertex.
struct AggregatedOperators {
  LaplaceOperators coarse;    ///< S_c = PᵀSP (#A by #A, PSD, S_c·1 = 0), mass_c = Pᵀmass (> 0), same total area.
  Eigen::VectorXi aggregate;  ///< #V aggregate index of every fine vertex, in [0, #A).
  Eigen::Index coarseSize() const { return coarse.mass.size(); }
};

/// Aggregates the vertices of (S, M) pass after pass as long as a pass leaves at least `minVertices` aggregates (and
/// merges something), and builds the Galerkin operators of the aggregates. With no such pass, the coarse level is
/// the fine one (P = I).
///
/// One pass is greedy graph aggregation on the pattern of S (as in smoothed-aggregation multigrid): every vertex not
/// yet taken, in index order, becomes a seed and takes its untaken neighbours; leftovers join a neighbouring
/// aggregate. On a triangle mesh a pass divides the vertex count by about 5–7, so 100k vertices need two or three
/// passes. Aggregates never span two connected components (they follow the edges of S), so S_c has exactly as many
/// zero eigenvalues as S.
/// Why Galerkin: S_c and mass_c are the restriction of the fine problem to piecewise-constant functions, so the
/// coarse eigenvectors prolonged by P are a cheap start for fine subspace iterations; their accuracy does not
/// matter for the final result, only the number of iterations does.
/// @param[in] ops  fine operators (S symmetric with the mesh's edge pattern, mass > 0).
/// @param[in] minVertices  lower bound on #A; the result has between minVertices and about 7·minVertices.
/// Cost: O(nnz(S)) per pass; memory O(nnz(S)).
AggregatedOperators aggregateOperators(const LaplaceOperators& ops, Eigen::Index minVertices);

/// X = P·Xc: every fine vertex takes its aggregate's row. @param[in] Xc  #A by k. @return #V by k. Cost: O(#V·k).
Eigen::MatrixXd prolong(const AggregatedOperators& levels, const Eigen::MatrixXd& Xc);

}  // namespace sc::spectral
