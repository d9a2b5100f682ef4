#include "spectral/repeated_eigenvalues.h"

#include "spectral/block_lanczos.h"
#include "spectral/lanczos_solver.h"

#include <algorithm>
#include <cmath>
#include <optional>
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

/// The range [first, last] of found values to count next, the point of the count and the pairs found below it.
struct CountedRange {
  Eigen::Index first{};
  Eigen::Index last{};
  double point{};
  Eigen::Index expected{};
  bool final{};  ///< nothing above it is counted afterwards
};

/// A single-vector run's whole result, or a block run's next cluster of at least kLanczosBlock values at or after
/// `from` that starts below index pairs; nullopt when none is left (see completeRepeatedEigenvalues()).
std::optional<CountedRange> nextRange(const Eigen::VectorXd& values, Eigen::Index from, int pairs, double scale,
                                      bool singleVectorRun) {
  const Eigen::Index found = values.size();
  const Eigen::Index limit = std::min<Eigen::Index>(pairs, found);
  CountedRange range{from, from, 0.0, 0, singleVectorRun};
  if (singleVectorRun) {
    range.first = 0;
    range.last = clusterEnd(values, limit - 1, scale);
  } else {
    for (; range.first < limit; range.first = range.last + 1) {
      range.last = clusterEnd(values, range.first, scale);
      if (range.last - range.first + 1 >= kLanczosBlock) break;
    }
    if (range.first >= limit) return std::nullopt;
  }
  const auto margin = [scale](double value) { return 0.5 * kClusterGap * (std::abs(value) + scale); };
  const Eigen::Index first = range.first;
  const Eigen::Index last = range.last;
  if (!singleVectorRun && last >= pairs - 1) {  // a block run's cluster that reaches index pairs − 1: count below it
    range.final = true;
    range.expected = first;
    range.point = first > 0 ? 0.5 * (values[first - 1] + values[first]) : values[first] - margin(values[first]);
  } else {
    range.expected = last + 1;
    range.point = last + 1 < found ? 0.5 * (values[last] + values[last + 1]) : values[last] + margin(values[last]);
  }
  return range;
}

/// Appends `more`'s pairs to `basis` and sorts them all ascending. Cost: #V·(both) doubles copied.
void appendPairs(HarmonicBasis& basis, const HarmonicBasis& more) {
  Eigen::VectorXd values(basis.eigenvalues.size() + more.eigenvalues.size());
  values << basis.eigenvalues, more.eigenvalues;
  Eigen::MatrixXd vectors(basis.vectors.rows(), values.size());
  vectors << basis.vectors, more.vectors;
  basis.eigenvalues = std::move(values);
  basis.vectors = std::move(vectors);
  sortAscending(basis);
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
  int runs = 0;
  Eigen::Index from = 0;
  while (const std::optional<CountedRange> range =
             nextRange(result.basis.eigenvalues, from, pairs, scale, singleVectorRun)) {
    if (options.progress && !options.progress(0.99)) {
      fail(result, BasisStatus::Cancelled, "cancelled");
      return;
    }
    Eigen::Index below = 0;
    try {
      op.set_shift(range->point);
      below = op.eigenvaluesBelowShift();
      if (below > range->expected && runs < kRounds) op.set_shift(sigma);
    } catch (const std::runtime_error& e) {
      fail(result, BasisStatus::FactorizationFailed, e.what());
      return;
    }
    if (below == range->expected) {
      if (range->final) break;
      from = range->last + 1;
      continue;
    }
    const std::string counts = std::to_string(below) + " eigenvalues lie below " + std::to_string(range->point) +
                               ", the eigensolver found " + std::to_string(range->expected);
    if (below < range->expected || runs == kRounds) {
      fail(result, BasisStatus::NotConverged,
           counts + " (copies of a repeated eigenvalue missing after " + std::to_string(runs) + " deflated runs)");
      return;
    }
    // at most one block's worth: those are copies of the missing eigenvalue, which the block spans at once (asked
    // for all six missing copies of the spheres' harmonic, the run did not converge in 64 columns)
    const int wanted = static_cast<int>(std::min<Eigen::Index>(below - range->expected, kLanczosBlock));
    const BasisResult more =
        blockLanczosNearestPairs(op, mass, wanted, 4 * wanted + 40, sigma, options, &result.basis.vectors);
    ++runs;
    result.operatorApplications = op.solveCount();
    if (!more.ok()) {
      fail(result, more.status, more.message);
      return;
    }
    if ((more.basis.eigenvalues.array() < range->point).count() == 0) {
      fail(result, BasisStatus::NotConverged, counts + ", and a deflated run found none of the missing ones");
      return;
    }
    appendPairs(result.basis, more.basis);  // then the same range is counted again
  }
  if (result.basis.eigenvalues.size() > pairs) {
    result.basis.eigenvalues.conservativeResize(pairs);
    result.basis.vectors.conservativeResize(Eigen::NoChange, pairs);
  }
}

}  // namespace sc::spectral::detail
