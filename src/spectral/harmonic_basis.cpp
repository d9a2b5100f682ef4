#include "spectral/harmonic_basis.h"

#include "spectral/component_localization.h"
#include "spectral/mesh_components.h"
#include "spectral/shift_invert_operator.h"

#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sc::spectral {
namespace {

using Solver = Spectra::SymGEigsShiftSolver<detail::ShiftInvertOperator, detail::DiagonalMassOperator,
                                            Spectra::GEigsMode::ShiftInvert>;

BasisResult failure(BasisStatus status, std::string message) {
  BasisResult result;
  result.status = status;
  result.message = std::move(message);
  return result;
}

/// Empty string when (S, mass, m) is a valid input, else the reason.
std::string validate(const LaplaceOperators& ops, int m) {
  const Eigen::Index n = ops.mass.size();
  if (ops.stiffness.rows() != n || ops.stiffness.cols() != n) return "stiffness and mass sizes differ";
  if (m < 1 || m >= n) return "m = " + std::to_string(m) + " must be in [1, #V) with #V = " + std::to_string(n);
  if (!(ops.mass.array() > 0.0).all() || !ops.mass.allFinite())
    return "the mass matrix has a non-positive or non-finite entry (unreferenced vertex or degenerate mesh)";
  if (!(ops.totalArea > 0.0)) return "the mesh has zero area";
  return {};
}

int lanczosSize(const BasisOptions& options, Eigen::Index n) {
  const int wanted = options.ncv > 0 ? options.ncv : std::max(5 * options.m / 2, options.m + 20);
  return static_cast<int>(std::min<Eigen::Index>(n, std::max(wanted, options.m + 1)));
}

/// Makes each column's entry of largest magnitude positive (first such entry on ties).
void fixSigns(Eigen::MatrixXd& H) {
  for (Eigen::Index k = 0; k < H.cols(); ++k) {
    Eigen::Index i = 0;
    H.col(k).cwiseAbs().maxCoeff(&i);
    if (H(i, k) < 0.0) H.col(k) = -H.col(k);
  }
}

}  // namespace

BasisResult manifoldHarmonicBasis(const LaplaceOperators& ops, const BasisOptions& options) {
  if (const std::string why = validate(ops, options.m); !why.empty()) return failure(BasisStatus::InvalidInput, why);

  // === step 1: shift-invert operator around σ < 0 (S − σM is SPD), progress estimated from the solve count
  const double sigma = -options.shiftFactor * 4.0 * std::numbers::pi / ops.totalArea;
  const double expectedSolves = 2.5 * options.m + 10.0;  // ≈ 251 at m = 100 (shared/design/spectral.md §2.2)
  auto observer = [&options, expectedSolves](int solves) {
    return !options.progress || options.progress(std::min(0.99, solves / expectedSolves));
  };
  detail::ShiftInvertOperator op(ops.stiffness, ops.mass, observer);
  detail::DiagonalMassOperator massOp(ops.mass);

  // === step 2: Lanczos in the M-inner product
  BasisResult result;
  try {
    Solver solver(op, massOp, options.m, lanczosSize(options, ops.mass.size()), sigma);
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, options.maxRestarts, options.tolerance,
                   Spectra::SortRule::SmallestAlge);
    if (solver.info() != Spectra::CompInfo::Successful)
      return failure(BasisStatus::NotConverged,
                     "the eigensolver did not converge (" + std::to_string(solver.num_iterations()) + " restarts)");
    result.basis.eigenvalues = solver.eigenvalues();
    result.basis.vectors = solver.eigenvectors();
  } catch (const detail::SolveCancelled&) {
    return failure(BasisStatus::Cancelled, "cancelled");
  } catch (const std::runtime_error& e) {
    return failure(BasisStatus::FactorizationFailed, e.what());
  }

  // === step 3: one component per eigenvector, deterministic signs and a final sanity check
  Eigen::VectorXi component;
  const int components = connectedComponents(ops.stiffness, component);
  localizeToComponents(component, components, ops.mass, result.basis.eigenvalues, result.basis.vectors);
  fixSigns(result.basis.vectors);
  result.basis.shift = sigma;
  result.operatorApplications = op.solveCount();
  if (!result.basis.vectors.allFinite() || !result.basis.eigenvalues.allFinite())
    return failure(BasisStatus::NotConverged, "the eigensolver returned non-finite values");
  result.status = BasisStatus::Ok;
  if (options.progress) options.progress(1.0);
  return result;
}

double orthonormalityError(const Eigen::MatrixXd& H, const Eigen::VectorXd& mass) {
  const Eigen::MatrixXd gram = H.transpose() * (mass.asDiagonal() * H);
  return (gram - Eigen::MatrixXd::Identity(H.cols(), H.cols())).cwiseAbs().maxCoeff();
}

const char* toString(BasisStatus status) {
  switch (status) {
    case BasisStatus::Ok:
      return "ok";
    case BasisStatus::InvalidInput:
      return "invalid input";
    case BasisStatus::FactorizationFailed:
      return "factorisation failed";
    case BasisStatus::NotConverged:
      return "not converged";
    case BasisStatus::Cancelled:
      return "cancelled";
  }
  return "unknown";
}

}  // namespace sc::spectral
