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

int largestCluster(const Eigen::VectorXd& values, double scale) {
  int largest = values.size() > 0 ? 1 : 0;
  int run = 1;
  for (Eigen::Index i = 1; i < values.size(); ++i) {
    run = sameCluster(values[i - 1], values[i], scale) ? run + 1 : 1;
    largest = std::max(largest, run);
  }
  return largest;
}

void completeRepeatedEigenvalues(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                                 const BasisOptions& options, BasisResult& result) {
  if (!result.ok()) return;
  const double scale = std::abs(sigma);
  Eigen::VectorXd& values = result.basis.eigenvalues;
  Eigen::MatrixXd& vectors = result.basis.vectors;
  const double halfGap = 0.5 * kClusterGap;
  int runs = 0;
  for (int from = 0;;) {
    // the next cluster of at least kLanczosBlock values [first, last] that starts below index pairs
    const auto found = static_cast<int>(values.size());
    int first = from;
    int last = from;
    for (; first < std::min(pairs, found); first = last + 1) {
      last = first;
      while (last + 1 < found && sameCluster(values[last], values[last + 1], scale)) ++last;
      if (last - first + 1 >= kLanczosBlock) break;
    }
    if (first >= std::min(pairs, found)) break;
    // a cluster that reaches index pairs − 1 needs only what lies below it counted; another, what lies up to its top
    const bool reachesEnd = last >= pairs - 1;
    const double point = reachesEnd ? (first > 0 ? 0.5 * (values[first - 1] + values[first])
                                                 : values[first] - halfGap * (std::abs(values[first]) + scale))
                                    : (last + 1 < found ? 0.5 * (values[last] + values[last + 1])
                                                        : values[last] + halfGap * (std::abs(values[last]) + scale));
    const int expected = reachesEnd ? first : last + 1;
    int below = 0;
    try {
      op.set_shift(point);
      below = op.eigenvaluesBelowShift();
      if (below > expected && runs < kRounds) op.set_shift(sigma);
    } catch (const std::runtime_error& e) {
      fail(result, BasisStatus::FactorizationFailed, e.what());
      return;
    }
    if (below == expected) {
      if (reachesEnd) break;
      from = last + 1;
      continue;
    }
    if (below < expected || runs == kRounds) {
      fail(result, BasisStatus::NotConverged,
           std::to_string(below) + " eigenvalues lie below " + std::to_string(point) + ", block Lanczos found " +
               std::to_string(expected) + " (copies of a repeated eigenvalue missing after " + std::to_string(runs) +
               " deflated runs)");
      return;
    }
    // at most one block's worth: those are copies of the missing eigenvalue, which the block spans at once (asked
    // for all six missing copies of the spheres' harmonic, the run did not converge in 64 columns)
    const int wanted = std::min(below - expected, kLanczosBlock);
    BasisResult more = blockLanczosNearestPairs(op, mass, wanted, 4 * wanted + 40, sigma, options, &vectors);
    ++runs;
    result.operatorApplications = op.solveCount();
    if (!more.ok()) {
      fail(result, more.status, more.message);
      return;
    }
    Eigen::VectorXd joinedValues(found + more.basis.eigenvalues.size());
    joinedValues << values, more.basis.eigenvalues;
    Eigen::MatrixXd joinedVectors(vectors.rows(), joinedValues.size());
    joinedVectors << vectors, more.basis.vectors;
    values = std::move(joinedValues);
    vectors = std::move(joinedVectors);
    sortPairs(values, vectors);  // then the same cluster is counted again
  }
  if (values.size() > pairs) {
    values.conservativeResize(pairs);
    vectors.conservativeResize(Eigen::NoChange, pairs);
  }
}

}  // namespace sc::spectral::detail
