#include "spectral/vertex_aggregation.h"

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

/// PᵀSP and Pᵀmass for the 0/1 prolongation given by `aggregate`.
LaplaceOperators galerkin(const LaplaceOperators& fine, const Eigen::VectorXi& aggregate, Eigen::Index aggregates) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(fine.stiffness.nonZeros()));
  for (Eigen::Index j = 0; j < fine.stiffness.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(fine.stiffness, j); it; ++it)
      triplets.emplace_back(aggregate(it.row()), aggregate(it.col()), it.value());
  LaplaceOperators coarse;
  coarse.stiffness.resize(aggregates, aggregates);
  coarse.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  coarse.mass = Eigen::VectorXd::Zero(aggregates);
  for (Eigen::Index i = 0; i < aggregate.size(); ++i) coarse.mass(aggregate(i)) += fine.mass(i);
  coarse.totalArea = fine.totalArea;
  coarse.mollifyEpsilon = fine.mollifyEpsilon;
  return coarse;
}

}  // namespace

AggregatedOperators aggregateOperators(const LaplaceOperators& ops, Eigen::Index minVertices) {
  AggregatedOperators out;
  out.coarse = ops;
  out.aggregate = Eigen::VectorXi::LinSpaced(ops.mass.size(), 0, static_cast<int>(ops.mass.size()) - 1);
  for (;;) {
    Eigen::Index aggregates = 0;
    const Eigen::VectorXi pass = aggregationPass(out.coarse.stiffness, aggregates);
    if (aggregates < minVertices || aggregates >= out.coarseSize()) break;  // too coarse, or nothing merged
    out.coarse = galerkin(out.coarse, pass, aggregates);
    for (Eigen::Index i = 0; i < out.aggregate.size(); ++i) out.aggregate(i) = pass(out.aggregate(i));
  }
  return out;
}

Eigen::MatrixXd prolong(const AggregatedOperators& levels, const Eigen::MatrixXd& Xc) {
  Eigen::MatrixXd X(levels.aggregate.size(), Xc.cols());
  for (Eigen::Index i = 0; i < X.rows(); ++i) X.row(i) = Xc.row(levels.aggregate(i));
  return X;
}

}  // namespace sc::spectral
