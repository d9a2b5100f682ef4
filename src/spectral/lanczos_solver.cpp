#include "spectral/lanczos_solver.h"

#include "spectral/shift_invert_operator.h"

#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace sc::spectral::detail {
namespace {

using Solver = Spectra::SymGEigsShiftSolver<ShiftInvertOperator, DiagonalMassOperator, Spectra::GEigsMode::ShiftInvert>;

int lanczosSize(const BasisOptions& options, int pairs, Eigen::Index n) {
  const int wanted = options.ncv > 0 ? options.ncv : std::max(5 * pairs / 2, pairs + 20);
  return static_cast<int>(std::min<Eigen::Index>(n, std::max(wanted, pairs + 1)));
}

}  // namespace

BasisResult lanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma, const BasisOptions& options) {
  const double expectedSolves = 2.5 * pairs + 10.0;  // ≈ 251 at m = 100 (shared/design/spectral.md §2.2)
  auto observer = [&options, expectedSolves](int solves) {
    return !options.progress || options.progress(std::min(0.99, solves / expectedSolves));
  };
  ShiftInvertOperator op(ops.stiffness, ops.mass, observer);
  DiagonalMassOperator massOp(ops.mass);
  BasisResult result;
  result.solver = BasisSolver::Lanczos;
  try {
    Solver solver(op, massOp, pairs, lanczosSize(options, pairs, ops.mass.size()), sigma);
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, options.maxRestarts, options.tolerance,
                   Spectra::SortRule::SmallestAlge);
    result.operatorApplications = op.solveCount();
    if (solver.info() != Spectra::CompInfo::Successful) {
      result.status = BasisStatus::NotConverged;
      result.message = "the eigensolver did not converge (" + std::to_string(solver.num_iterations()) + " restarts)";
      return result;
    }
    result.basis.eigenvalues = solver.eigenvalues();
    result.basis.vectors = solver.eigenvectors();
  } catch (const SolveCancelled&) {
    result.status = BasisStatus::Cancelled;
    result.message = "cancelled";
    return result;
  } catch (const std::runtime_error& e) {
    result.status = BasisStatus::FactorizationFailed;
    result.message = e.what();
    return result;
  }
  result.status = BasisStatus::Ok;
  return result;
}

}  // namespace sc::spectral::detail
