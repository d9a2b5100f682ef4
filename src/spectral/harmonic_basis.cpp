#include "spectral/harmonic_basis.h"

#include "spectral/component_localization.h"
#include "spectral/hierarchical_basis.h"
#include "spectral/huge_pages.h"
#include "spectral/lanczos_solver.h"
#include "spectral/mesh_components.h"
#include "spectral/parallel_ranges.h"
#include "spectral/spectrum_slices.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

namespace sc::spectral {
namespace {

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

/// Makes each column's entry of largest magnitude positive (first such entry on ties).
void fixSigns(Eigen::MatrixXd& H) {
  for (Eigen::Index k = 0; k < H.cols(); ++k) {
    Eigen::Index i = 0;
    H.col(k).cwiseAbs().maxCoeff(&i);
    if (H(i, k) < 0.0) H.col(k) = -H.col(k);
  }
}

BasisResult eigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options) {
  switch (options.solver) {
    case BasisSolver::Hierarchical:
      return detail::hierarchicalEigenpairs(ops, sigma, options);
    case BasisSolver::Slices:
      return detail::slicedEigenpairs(ops, sigma, options);
    case BasisSolver::Lanczos:
      break;
  }
  return detail::lanczosEigenpairs(ops, options.m, sigma, options);
}

}  // namespace

BasisResult manifoldHarmonicBasis(const LaplaceOperators& ops, const BasisOptions& options) {
  if (const std::string why = validate(ops, options.m); !why.empty()) return failure(BasisStatus::InvalidInput, why);

  // === step 1: eigenpairs around σ < 0 (S − σM is SPD)
  const double sigma = -options.shiftFactor * 4.0 * std::numbers::pi / ops.totalArea;
  BasisResult result = eigenpairs(ops, sigma, options);
  if (!result.ok()) return result;

  // === step 2: one component per eigenvector, deterministic signs and a final sanity check
  Eigen::VectorXi component;
  const int components = connectedComponents(ops.stiffness, component);
  localizeToComponents(component, components, ops.mass, result.basis.eigenvalues, result.basis.vectors);
  fixSigns(result.basis.vectors);
  result.basis.shift = sigma;
  if (!result.basis.vectors.allFinite() || !result.basis.eigenvalues.allFinite())
    return failure(BasisStatus::NotConverged, "the eigensolver returned non-finite values");
  result.maxResidual = maxRelativeResidual(ops, result.basis);
  if (options.progress) options.progress(1.0);
  return result;
}

double maxRelativeResidual(const LaplaceOperators& ops, const HarmonicBasis& basis) {
  constexpr Eigen::Index kChunk = 8;
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, kChunk, Eigen::RowMajor>;
  const Eigen::Index n = basis.vectors.rows();
  const Eigen::Index chunks = (basis.size() + kChunk - 1) / kChunk;
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<double> worst(static_cast<std::size_t>(chunks), 0.0);
  detail::parallelRanges(chunks, threads, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    // Row-major chunks, so that the product reads S once per chunk (Eigen multiplies a column-major right-hand side
    // one column at a time: a read of S per column); and buffers reused across chunks, since fresh #V × 8 temporaries
    // cost a page fault per 4 KB each time. Both took the check at 1M vertices from 1.7 s to 0.7 s.
    Rows h(n, kChunk);
    Rows sh(n, kChunk);
    detail::adviseHugePages(h.data(), static_cast<std::size_t>(h.size()) * sizeof(double));
    detail::adviseHugePages(sh.data(), static_cast<std::size_t>(sh.size()) * sizeof(double));
    for (std::ptrdiff_t chunk = begin; chunk < end; ++chunk) {
      const Eigen::Index first = chunk * kChunk;
      const Eigen::Index count = std::min(kChunk, basis.size() - first);
      h.leftCols(count) = basis.vectors.middleCols(first, count);
      h.rightCols(kChunk - count).setZero();
      sh.noalias() = ops.stiffness * h;
      Eigen::Matrix<double, 1, kChunk> lambda = Eigen::Matrix<double, 1, kChunk>::Zero();
      lambda.head(count) = basis.eigenvalues.segment(first, count).transpose();
      Eigen::Matrix<double, 1, kChunk> squared = Eigen::Matrix<double, 1, kChunk>::Zero();  // ‖S h − λ M h‖²_{M⁻¹}
      for (Eigen::Index i = 0; i < n; ++i) {
        const double mass = ops.mass[i];
        squared += (sh.row(i) - mass * lambda.cwiseProduct(h.row(i))).cwiseAbs2() / mass;
      }
      const Eigen::ArrayXd relative = squared.head(count).transpose().array().sqrt() /
                                      (lambda.head(count).transpose().array().abs() + std::abs(basis.shift));
      worst[static_cast<std::size_t>(chunk)] = relative.maxCoeff();
    }
  });
  return worst.empty() ? 0.0 : *std::max_element(worst.begin(), worst.end());
}

double orthonormalityError(const Eigen::MatrixXd& H, const Eigen::VectorXd& mass) {
  constexpr Eigen::Index kBand = 4096;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(H.cols(), H.cols());
  Eigen::MatrixXd weighted;
  for (Eigen::Index row = 0; row < H.rows(); row += kBand) {
    const Eigen::Index rows = std::min(kBand, H.rows() - row);
    const auto band = H.middleRows(row, rows);
    weighted.noalias() = mass.segment(row, rows).asDiagonal() * band;
    gram.noalias() += band.transpose() * weighted;
  }
  return (gram - Eigen::MatrixXd::Identity(H.cols(), H.cols())).cwiseAbs().maxCoeff();
}

const char* toString(BasisSolver solver) {
  switch (solver) {
    case BasisSolver::Hierarchical:
      return "hierarchical";
    case BasisSolver::Slices:
      return "slices";
    case BasisSolver::Lanczos:
      break;
  }
  return "lanczos";
}

std::optional<BasisSolver> basisSolverNamed(std::string_view name) {
  for (const BasisSolver solver : {BasisSolver::Lanczos, BasisSolver::Slices, BasisSolver::Hierarchical})
    if (name == toString(solver)) return solver;
  return std::nullopt;
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
