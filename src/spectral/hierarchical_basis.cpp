#include "spectral/hierarchical_basis.h"

#include "spectral/lanczos_solver.h"
#include "spectral/subspace_iteration.h"
#include "spectral/vertex_aggregation.h"

#include <algorithm>
#include <string>

namespace sc::spectral::detail {
namespace {

constexpr double kCoarseShare = 0.1;  ///< progress fraction reported for the coarse level

}  // namespace

BasisResult hierarchicalEigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options) {
  const Eigen::Index n = ops.mass.size();
  const int guard = options.guardVectors > 0 ? options.guardVectors : std::max(options.m / 2, 16);
  const int b = options.m + guard;

  // === step 1: coarse level (or Lanczos on the mesh itself when it is too small to coarsen)
  const AggregatedOperators levels = aggregateOperators(ops, 8 * static_cast<Eigen::Index>(b));
  if (levels.coarseSize() == n) return lanczosEigenpairs(ops, options.m, sigma, options);

  // === step 2: the b smallest coarse eigenpairs, prolonged
  BasisOptions coarseOptions = options;
  coarseOptions.tolerance = 1e-6;
  coarseOptions.ncv = 0;
  coarseOptions.progress = [&options](double fraction) {
    return !options.progress || options.progress(kCoarseShare * fraction);
  };
  BasisResult coarse = lanczosEigenpairs(levels.coarse, b, sigma, coarseOptions);
  if (!coarse.ok()) {
    coarse.message = "coarse level: " + coarse.message;
    return coarse;
  }

  // === step 3: subspace iteration on the fine mesh
  SubspaceIterationOptions fine;
  fine.wanted = options.m;
  fine.tolerance = options.residualTolerance;
  fine.maxSweeps = options.maxSweeps;
  fine.progress = [&options](double fraction) {
    return !options.progress || options.progress(kCoarseShare + (1.0 - kCoarseShare) * fraction);
  };
  SubspaceIterationResult solved = subspaceIteration(ops, sigma, prolong(levels, coarse.basis.vectors), fine);

  BasisResult result;
  result.solver = BasisSolver::Hierarchical;
  result.sweeps = solved.sweeps;
  result.operatorApplications = coarse.operatorApplications + solved.solves;
  switch (solved.status) {
    case SubspaceIterationResult::Status::Converged:
      result.status = BasisStatus::Ok;
      result.basis.eigenvalues = std::move(solved.eigenvalues);
      result.basis.vectors = std::move(solved.vectors);
      result.maxResidual = solved.residuals.maxCoeff();
      break;
    case SubspaceIterationResult::Status::NotConverged:
      result.status = BasisStatus::NotConverged;
      result.message = "subspace iteration did not converge in " + std::to_string(solved.sweeps) + " sweeps";
      break;
    case SubspaceIterationResult::Status::FactorizationFailed:
      result.status = BasisStatus::FactorizationFailed;
      result.message = "Cholesky factorisation of S - sigma*M failed (S not PSD or M singular)";
      break;
    case SubspaceIterationResult::Status::Cancelled:
      result.status = BasisStatus::Cancelled;
      result.message = "cancelled";
      break;
  }
  return result;
}

}  // namespace sc::spectral::detail
