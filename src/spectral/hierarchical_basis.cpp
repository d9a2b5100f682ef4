#include "spectral/hierarchical_basis.h"

#include "spectral/lanczos_solver.h"
#include "spectral/subspace_iteration.h"
#include "spectral/vertex_aggregation.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace sc::spectral::detail {
namespace {

constexpr double kCoarseShare = 0.2;  ///< progress fraction reported for the coarse levels
/// Residual tolerance on the intermediate levels: their pairs only start the next finer level, whose own
/// discretisation error (relative residual ≈ 0.1 after one solve on the 100k dragon) dwarfs anything tighter.
constexpr double kIntermediateTolerance = 1e-3;

BasisResult failure(BasisStatus status, std::string message) {
  BasisResult r;
  r.solver = BasisSolver::Hierarchical;
  r.status = status;
  r.message = std::move(message);
  return r;
}

BasisResult fromSubspace(SubspaceIterationResult solved, const std::string& where) {
  switch (solved.status) {
    case SubspaceIterationResult::Status::Converged:
      break;
    case SubspaceIterationResult::Status::NotConverged:
      return failure(BasisStatus::NotConverged,
                     where + "subspace iteration did not converge in " + std::to_string(solved.sweeps) + " sweeps");
    case SubspaceIterationResult::Status::FactorizationFailed:
      return failure(BasisStatus::FactorizationFailed,
                     where + "Cholesky factorisation of S - sigma*M failed (S not PSD or M singular)");
    case SubspaceIterationResult::Status::Cancelled:
      return failure(BasisStatus::Cancelled, "cancelled");
  }
  BasisResult result;
  result.status = BasisStatus::Ok;
  result.solver = BasisSolver::Hierarchical;
  result.sweeps = solved.sweeps;
  result.basis.eigenvalues = std::move(solved.eigenvalues);
  result.basis.vectors = std::move(solved.vectors);
  result.maxResidual = solved.residuals.maxCoeff();
  return result;
}

}  // namespace

BasisResult hierarchicalEigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options) {
  const int guard = options.guardVectors > 0 ? options.guardVectors : std::max(options.m / 2, 16);
  const int b = options.m + guard;

  // === step 1: the coarse levels (or Lanczos on the mesh itself when it is too small to coarsen)
  const std::vector<AggregatedOperators> levels = aggregationHierarchy(ops, 2 * static_cast<Eigen::Index>(b));
  if (levels.empty()) return lanczosEigenpairs(ops, options.m, sigma, options);
  const int levelCount = static_cast<int>(levels.size());

  // === step 2: the b smallest eigenpairs of the coarsest level
  BasisOptions coarseOptions = options;
  coarseOptions.tolerance = 1e-6;
  coarseOptions.ncv = 0;
  coarseOptions.progress = [&options, levelCount](double fraction) {
    return !options.progress || options.progress(kCoarseShare * fraction / levelCount);
  };
  const BasisResult coarse = lanczosEigenpairs(levels.back().coarse, b, sigma, coarseOptions);
  if (!coarse.ok()) return failure(coarse.status, "coarse level: " + coarse.message);
  int solves = coarse.operatorApplications;

  // === step 3: level by level up to the mesh, subspace iterations from the prolonged block
  Eigen::MatrixXd start = levels.back().prolongation * coarse.basis.vectors;
  for (int k = levelCount - 2;; --k) {
    const bool fine = k < 0;
    const LaplaceOperators& level = fine ? ops : levels[static_cast<std::size_t>(k)].coarse;
    SubspaceIterationOptions iteration;
    iteration.wanted = options.m;
    iteration.tolerance = fine ? options.residualTolerance : kIntermediateTolerance;
    iteration.maxSweeps = options.maxSweeps;
    const double from = fine ? kCoarseShare : kCoarseShare * (levelCount - 1 - k) / levelCount;
    const double to = fine ? 1.0 : kCoarseShare * (levelCount - k) / levelCount;
    iteration.progress = [&options, from, to](double fraction) {
      return !options.progress || options.progress(from + (to - from) * fraction);
    };
    SubspaceIterationResult solved = subspaceIteration(level, sigma, std::move(start), iteration);
    solves += solved.solves;
    if (fine || solved.status != SubspaceIterationResult::Status::Converged) {
      BasisResult result = fromSubspace(std::move(solved), fine ? "" : "coarse level: ");
      result.operatorApplications = solves;
      return result;
    }
    Eigen::MatrixXd block(solved.vectors.rows(), b);
    block << solved.vectors, solved.guard;
    start = levels[static_cast<std::size_t>(k)].prolongation * block;
  }
}

}  // namespace sc::spectral::detail
