#include "spectral/vertex_aggregation.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sc::spectral {
namespace {

/// One greedy aggregation pass on the pattern of the symmetric matrix S; returns the aggregate of every row.
Eigen::VectorXi aggregationPass(const SparseMatrix& S, Eigen::Index& aggregates) {
  const Eigen::Index n = S.rows();
  Eigen::VectorXi aggregate = Eigen::VectorXi::Constant(n, -1);
  aggregates = 0;
  // seeds: a vertex whose neighbours are all free takes them
  for (Eigen::Index i = 0; i < n; ++i) {
    if (aggregate(i) >= 0) continue;
    bool free = true;
    for (SparseMatrix::InnerIterator it(S, i); it && free; ++it) free = aggregate(it.row()) < 0;
    if (!free) continue;
    for (SparseMatrix::InnerIterator it(S, i); it; ++it) aggregate(it.row()) = static_cast<int>(aggregates);
    aggregate(i) = static_cast<int>(aggregates++);
  }
  // leftovers join a neighbouring aggregate, or (isolated from every aggregate) form their own
  for (Eigen::Index i = 0; i < n; ++i) {
    if (aggregate(i) >= 0) continue;
    for (SparseMatrix::InnerIterator it(S, i); it; ++it)
      if (aggregate(it.row()) >= 0) {
        aggregate(i) = aggregate(it.row());
        break;
      }
    if (aggregate(i) < 0) aggregate(i) = static_cast<int>(aggregates++);
  }
  return aggregate;
}

/// P = (I − ω D⁻¹S) P₀ for the 0/1 prolongation P₀ given by `aggregate`.
SparseMatrix smoothedProlongation(const SparseMatrix& S, const Eigen::VectorXi& aggregate, Eigen::Index aggregates) {
  const Eigen::Index n = S.rows();
  Eigen::VectorXd inverseDiagonal(n);
  double rho = 0.0;  // Gershgorin bound on ρ(D⁻¹S)
  for (Eigen::Index j = 0; j < n; ++j) {
    double diagonal = 0.0, absolute = 0.0;
    for (SparseMatrix::InnerIterator it(S, j); it; ++it) {
      absolute += std::abs(it.value());
      if (it.row() == j) diagonal = it.value();
    }
    inverseDiagonal(j) = diagonal > 0.0 ? 1.0 / diagonal : 0.0;  // a zero row (isolated vertex) stays unsmoothed
    if (diagonal > 0.0) rho = std::max(rho, absolute / diagonal);
  }
  const double omega = rho > 0.0 ? (4.0 / 3.0) / rho : 0.0;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(S.nonZeros() + n));
  for (Eigen::Index i = 0; i < n; ++i) triplets.emplace_back(i, aggregate(i), 1.0);
  // S symmetric: column j's entries S_ij are row j's, so −ω S_ij / S_ii goes to (i, aggregate(j))
  for (Eigen::Index j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(S, j); it; ++it)
      triplets.emplace_back(it.row(), aggregate(j), -omega * inverseDiagonal(it.row()) * it.value());
  SparseMatrix P(n, aggregates);
  P.setFromTriplets(triplets.begin(), triplets.end());
  return P;
}

AggregatedOperators coarsen(const LaplaceOperators& fine, Eigen::VectorXi aggregate, Eigen::Index aggregates) {
  AggregatedOperators level;
  level.prolongation = smoothedProlongation(fine.stiffness, aggregate, aggregates);
  level.aggregate = std::move(aggregate);
  const SparseMatrix SP = fine.stiffness * level.prolongation;
  const SparseMatrix Pt = level.prolongation.transpose();
  SparseMatrix Sc = Pt * SP;
  level.coarse.stiffness = 0.5 * (Sc + SparseMatrix(Sc.transpose()));
  level.coarse.mass = Pt * fine.mass;
  level.coarse.totalArea = fine.totalArea;
  level.coarse.mollifyEpsilon = fine.mollifyEpsilon;
  return level;
}

}  // namespace

std::vector<AggregatedOperators> aggregationHierarchy(const LaplaceOperators& ops, Eigen::Index minVertices) {
  std::vector<AggregatedOperators> levels;
  for (;;) {
    const LaplaceOperators& finer = levels.empty() ? ops : levels.back().coarse;
    Eigen::Index aggregates = 0;
    Eigen::VectorXi pass = aggregationPass(finer.stiffness, aggregates);
    if (aggregates < minVertices || aggregates >= finer.mass.size()) break;  // too coarse, or nothing merged
    AggregatedOperators level = coarsen(finer, std::move(pass), aggregates);
    if (!(level.coarse.mass.minCoeff() > 0.0)) break;  // smoothing made an aggregate's mass vanish: stop here
    levels.push_back(std::move(level));
  }
  return levels;
}

}  // namespace sc::spectral
