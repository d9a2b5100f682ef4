#include "spectral/lanczos_solver.h"

#include "spectral/single_threaded_blas.h"

#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace sc::spectral::detail {
namespace {

using Solver = Spectra::SymGEigsShiftSolver<ShiftInvertOperator, DiagonalMassOperator, Spectra::GEigsMode::ShiftInvert>;

}  // namespace

void sortAscending(HarmonicBasis& basis) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(basis.eigenvalues.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(),
                   [&basis](Eigen::Index a, Eigen::Index b) { return basis.eigenvalues[a] < basis.eigenvalues[b]; });
  if (std::is_sorted(order.begin(), order.end())) return;
  Eigen::VectorXd values(basis.eigenvalues.size());
  Eigen::MatrixXd vectors(basis.vectors.rows(), basis.vectors.cols());
  for (std::size_t i = 0; i < order.size(); ++i) {
    values[static_cast<Eigen::Index>(i)] = basis.eigenvalues[order[i]];
    vectors.col(static_cast<Eigen::Index>(i)) = basis.vectors.col(order[i]);
  }
  basis.eigenvalues = std::move(values);
  basis.vectors = std::move(vectors);
}

BasisResult lanczosNearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, int ncv, double sigma,
                                const BasisOptions& options) {
  DiagonalMassOperator massOp(mass);
  BasisResult result;
  result.solver = BasisSolver::Lanczos;
  try {
    const int size = static_cast<int>(std::min<Eigen::Index>(mass.size(), std::max(ncv, pairs + 1)));
    Solver solver(op, massOp, pairs, size, sigma);
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
  sortAscending(result.basis);
  result.basis.shift = sigma;
  result.status = BasisStatus::Ok;
  return result;
}

BasisResult lanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma, const BasisOptions& options) {
  const double expectedSolves = 2.5 * pairs + 10.0;  // ≈ 251 at m = 100 (shared/design/spectral.md §2.2)
  auto observer = [&options, expectedSolves](int solves) {
    return !options.progress || options.progress(std::min(0.99, solves / expectedSolves));
  };
  ShiftInvertOperator op(ops.stiffness, ops.mass, observer);
  const int ncv = options.ncv > 0 ? options.ncv : std::max(5 * pairs / 2, pairs + 20);
  // Spectra's ~750 GEMVs are small: OpenBLAS's second thread saves 0.05–0.3 s when the cores are idle (7.5k and 10k
  // meshes), but waits for a time slice at each of them when they are not (5.1 s against 0.34–0.61 s with one thread
  // while two busy processes held the 2 cores)
  const SingleThreadedBlas oneBlasThread;
  return lanczosNearestPairs(op, ops.mass, pairs, ncv, sigma, options);
}

}  // namespace sc::spectral::detail
