#include "spectral/repeated_eigenvalues.h"

#include "spectral/block_lanczos.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace sc::spectral::detail {
namespace {

/// Deflated runs before a count is given up on (each finds up to kLanczosBlock missing copies).
constexpr int kRounds = 16;

bool sameCluster(double lower, double upper, double scale) {
  return upper - lower < kClusterGap * (std::abs(upper) + scale);
}

/// Ascending by eigenvalue, vectors reordered with them.
void sortPairs(Eigen::VectorXd& values, Eigen::MatrixXd& vectors) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(values.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(),
                   [&values](Eigen::Index a, Eigen::Index b) { return values[a] < values[b]; });
  Eigen::VectorXd sortedValues(values.size());
  Eigen::MatrixXd sortedVectors(vectors.rows(), vectors.cols());
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    sortedValues[i] = values[order[static_cast<std::size_t>(i)]];
    sortedVectors.col(i) = vectors.col(order[static_cast<std::size_t>(i)]);
  }
  values = std::move(sortedValues);
  vectors = std::move(sortedVectors);
}

void fail(BasisResult& result, BasisStatus status, std::string message) {
  result.status = status;
  result.message = std::move(message);
  result.basis = {};
}

}  // namespace

Eigen::Index clusterEnd(const Eigen::VectorXd& values, Eigen::Index first, double scale) {
  Eigen::Index last = first;
  while (last + 1 < values.size() && sameCluster(values[first], values[last + 1], scale)) ++last;
  return last;
}

void completeRepeatedEigenvalues(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                                 const BasisOptions& options, bool singleVectorRun, BasisResult& result) {
  if (!result.ok() || result.basis.eigenvalues.size() == 0) return;
  const double scale = std::abs(sigma);
  Eigen::VectorXd& values = result.basis.eigenvalues;
  Eigen::MatrixXd& vectors = result.basis.vectors;
  const auto margin = [scale](double value) { return 0.5 * kClusterGap * (std::abs(value) + scale); };
  int runs = 0;
  for (Eigen::Index from = 0;;) {
    const auto found = static_cast<Eigen::Index>(values.size());
    const Eigen::Index limit = std::min<Eigen::Index>(pairs, found);
    // the range [first, last] to count: a single-vector run's whole result, or a block run's next large cluster
    Eigen::Index first = from;
    Eigen::Index last = from;
    if (singleVectorRun) {
      first = 0;
      last = clusterEnd(values, limit - 1, scale);
    } else {
      for (; first < limit; first = last + 1) {
        last = clusterEnd(values, first, scale);
        if (last - first + 1 >= kLanczosBlock) break;
      }
      if (first >= limit) break;
    }
    const bool countBelowIt = !singleVectorRun && last >= pairs - 1;
    const double point =
        countBelowIt
            ? (first > 0 ? 0.5 * (values[first - 1] + values[first]) : values[first] - margin(values[first]))
            : (last + 1 < found ? 0.5 * (values[last] + values[last + 1]) : values[last] + margin(values[last]));
    const Eigen::Index expected = countBelowIt ? first : last + 1;
    if (options.progress && !options.progress(0.99)) {
      fail(result, BasisStatus::Cancelled, "cancelled");
      return;
    }
    Eigen::Index below = 0;
    try {
      op.set_shift(point);
      below = op.eigenvaluesBelowShift();
      if (below > expected && runs < kRounds) op.set_shift(sigma);
    } catch (const std::runtime_error& e) {
      fail(result, BasisStatus::FactorizationFailed, e.what());
      return;
    }
    if (below == expected) {
      if (singleVectorRun || countBelowIt) break;
      from = last + 1;
      continue;
    }
    const std::string counts = std::to_string(below) + " eigenvalues lie below " + std::to_string(point) +
                               ", the eigensolver found " + std::to_string(expected);
    if (below < expected || runs == kRounds) {
      fail(result, BasisStatus::NotConverged,
           counts + " (copies of a repeated eigenvalue missing after " + std::to_string(runs) + " deflated runs)");
      return;
    }
    // at most one block's worth: those are copies of the missing eigenvalue, which the block spans at once (asked
    // for all six missing copies of the spheres' harmonic, the run did not converge in 64 columns)
    const int wanted = static_cast<int>(std::min<Eigen::Index>(below - expected, kLanczosBlock));
    BasisResult more = blockLanczosNearestPairs(op, mass, wanted, 4 * wanted + 40, sigma, options, &vectors);
    ++runs;
    result.operatorApplications = op.solveCount();
    if (!more.ok()) {
      fail(result, more.status, more.message);
      return;
    }
    if ((more.basis.eigenvalues.array() < point).count() == 0) {
      fail(result, BasisStatus::NotConverged, counts + ", and a deflated run found none of the missing ones");
      return;
    }
    Eigen::VectorXd joinedValues(found + more.basis.eigenvalues.size());
    joinedValues << values, more.basis.eigenvalues;
    Eigen::MatrixXd joinedVectors(vectors.rows(), joinedValues.size());
    joinedVectors << vectors, more.basis.vectors;
    values = std::move(joinedValues);
    vectors = std::move(joinedVectors);
    sortPairs(values, vectors);  // then the same range is counted again
  }
  if (values.size() > pairs) {
    values.conservativeResize(pairs);
    vectors.conservativeResize(Eigen::NoChange, pairs);
  }
}

}  // namespace sc::spectral::detail
