#include "spectral/block_lanczos.h"

#include "spectral/huge_pages.h"
#include "spectral/krylov_basis.h"
#include "spectral/lanczos_solver.h"
#include "spectral/reorthogonalisation_schedule.h"
#include "spectral/vertex_order.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace sc::spectral::detail {
namespace {

constexpr unsigned kSeed = 0x5eed;
/// Applications of the operator to the random start block before it becomes the first Krylov block.
constexpr int kStartSmoothing = 2;

/// Ritz pairs of the projected matrix that are wanted and converged, or the reason they are not yet.
struct RitzCheck {
  bool converged = false;
  Eigen::VectorXd theta;        ///< the `pairs` wanted Ritz values (largest |θ|)
  Eigen::MatrixXd coordinates;  ///< their eigenvectors in the Krylov basis
};

RitzCheck checkRitzPairs(const KrylovBasis& krylov, const Eigen::MatrixXd& coupling, int pairs, double tolerance) {
  const Eigen::Index k = krylov.size();
  const Eigen::MatrixXd t = krylov.projected().topLeftCorner(k, k);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (t + t.transpose()));
  RitzCheck check;
  if (eigen.info() != Eigen::Success) return check;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(k));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  const Eigen::VectorXd& theta = eigen.eigenvalues();
  std::stable_sort(order.begin(), order.end(),
                   [&theta](Eigen::Index a, Eigen::Index b) { return std::abs(theta[a]) > std::abs(theta[b]); });
  const double floor = std::pow(std::numeric_limits<double>::epsilon(), 2.0 / 3.0);
  check.theta.resize(pairs);
  check.coordinates.resize(k, pairs);
  check.converged = true;
  for (int i = 0; i < pairs; ++i) {
    const Eigen::Index j = order[static_cast<std::size_t>(i)];
    check.theta[i] = theta[j];
    check.coordinates.col(i) = eigen.eigenvectors().col(j);
    // ‖Op y − θ y‖_M = ‖R s_last‖: the next block's coupling times the Ritz vector's last-block coordinates
    const double residual = (coupling * eigen.eigenvectors().col(j).tail(kLanczosBlock)).norm();
    if (residual > tolerance * std::max(std::abs(theta[j]), floor)) check.converged = false;
  }
  return check;
}

/// Blocks between two Ritz checks: each block when the check costs at most an eighth of a block, else every few,
/// but at least every pairs/24 blocks (the earlier fixed rule; small meshes check often, their blocks are cheap).
/// The check (a dense eigen-decomposition of the K × K projected matrix) took 1–3 ms at K ≤ 200, about 0.4 ns·K³;
/// a block's four solves take at least 150 ns·#V (3.7 ms per right-hand side at 100k vertices, 25 ms at 437k). At
/// 100k and 60 pairs that is every second block; at 437k and 1M every block, which ended the 1M run (m = 100) 12
/// solves and 96 MB of basis earlier than every fourth block did. Deterministic (no timing), so results reproduce.
int ritzCheckInterval(Eigen::Index n, int pairs) {
  const double columns = 2.2 * pairs + 55.0;  // the usual K at convergence
  const double blocks = columns * columns * columns / (47.0 * static_cast<double>(n));
  return std::clamp(static_cast<int>(std::ceil(blocks)), 1, std::max(1, pairs / (6 * kLanczosBlock)));
}

/// The converged Ritz pairs as a result: eigenvalues λ = σ + 1/θ ascending, vectors formed in the Krylov basis (whose
/// rows are in `rows`) and put back in the mesh's vertex order on `threads`.
BasisResult convergedPairs(const RitzCheck& check, KrylovBasis&& krylov, const VertexOrder& rows, int threads,
                           double sigma, int solves) {
  const auto pairs = check.theta.size();
  BasisResult result;
  result.solver = BasisSolver::Lanczos;
  result.operatorApplications = solves;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(pairs));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  const Eigen::VectorXd lambda = (1.0 / check.theta.array()).matrix().array() + sigma;
  std::sort(order.begin(), order.end(), [&lambda](Eigen::Index a, Eigen::Index b) { return lambda[a] < lambda[b]; });
  Eigen::MatrixXd coordinates(krylov.size(), pairs);
  result.basis.eigenvalues.resize(pairs);
  for (Eigen::Index i = 0; i < pairs; ++i) {
    coordinates.col(i) = check.coordinates.col(order[static_cast<std::size_t>(i)]);
    result.basis.eigenvalues[i] = lambda[order[static_cast<std::size_t>(i)]];
  }
  result.basis.vectors = std::move(krylov).ritzVectors(coordinates);
  rows.scatterInPlace(result.basis.vectors, threads);
  result.basis.shift = sigma;
  result.status = BasisStatus::Ok;
  return result;
}

BasisResult failure(BasisStatus status, std::string message, const ShiftInvertOperator& op) {
  BasisResult result;
  result.solver = BasisSolver::Lanczos;
  result.status = status;
  result.message = std::move(message);
  result.operatorApplications = op.solveCount();
  return result;
}

}  // namespace

BasisResult blockLanczosNearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, int maxColumns,
                                     double sigma, const BasisOptions& options, const Eigen::MatrixXd* deflation) {
  const Eigen::Index n = mass.size();
  const Eigen::Index least = pairs + 2 * kLanczosBlock;
  const Eigen::Index capacity =
      std::min<Eigen::Index>(std::max<Eigen::Index>(maxColumns, least), n / 2) / kLanczosBlock * kLanczosBlock;
  if (pairs < 1 || capacity < least)
    return failure(BasisStatus::NotConverged, "the mesh is too small for block Lanczos", op);
  try {
    // The run keeps every #V-vector in the factor's vertex order, so that its solves skip CHOLMOD's permutations
    // (ShiftInvertOperator::solveInFactorOrder()): M and the deflation columns are gathered into it once the factor
    // exists (below), the basis refers to them from the start, and the Ritz vectors are scattered back at the end.
    Eigen::VectorXd orderedMass(n);
    Eigen::MatrixXd orderedDeflation;
    KrylovBasis krylov(orderedMass, capacity, op.solveThreads(), deflation != nullptr ? &orderedDeflation : nullptr);
    {
      // The basis's pages are fresh: their first writes took 5 s of page faults at 1M vertices (about 8 µs per 4 KB
      // page on the measuring VM). With a core to spare (the large-mesh run), the columns a run needs
      // (2.2·pairs + 40, a little under the usual K ≈ 2.2·pairs + 55, so that none is touched in vain) are written on
      // it while this thread factors, which takes longer.
      std::jthread toucher;
      if (op.solveThreads() > 1) {
        const auto usual = static_cast<Eigen::Index>(2.2 * pairs + 40.0);
        toucher = std::jthread([&krylov, usual] { krylov.touch(usual); });
      }
      op.set_shift(sigma);
    }
    const VertexOrder order(op.factorOrder());
    orderedMass = order.gather(mass);
    if (deflation != nullptr) orderedDeflation = order.gather(*deflation);
    // a deflated run starts elsewhere: from the first run's start block, whose part in each eigenspace the found
    // vectors already span, deflation would leave nothing of a missing copy
    std::mt19937 random(kSeed + (deflation != nullptr ? static_cast<unsigned>(deflation->cols()) : 0U));
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    // drawn in the mesh's order, so that the start does not depend on the factor's
    Eigen::MatrixXd w = order.gather(Eigen::MatrixXd::NullaryExpr(n, kLanczosBlock, [&] { return uniform(random); }));
    // A random block carries every frequency; (S − σM)⁻¹M damps the high ones by their |θ|, which S would amplify
    // again in ‖Sh − λMh‖ (by up to λ_max/λ: 7e-5 instead of 3e-7 on the 1M mesh's slivers). Two applications keep
    // them out of every Krylov vector and so out of the Ritz vectors (ARPACK puts its start in the operator's range
    // the same way).
    // The right-hand sides M·W, in one buffer for the whole run: a fresh #V × 4 temporary per block is 32 MB at 1M
    // vertices, which glibc maps and unmaps each time (at or above its largest mmap threshold), so every block paid
    // 8,192 page faults: 600,000 in the 1M basis.
    Eigen::MatrixXd rightHandSides(n, kLanczosBlock);
    adviseHugePages(rightHandSides.data(), static_cast<std::size_t>(rightHandSides.size()) * sizeof(double));
    krylov.deflate(w);
    for (int smoothing = 0; smoothing < kStartSmoothing; ++smoothing) {
      rightHandSides.noalias() = orderedMass.asDiagonal() * w;
      op.solveInFactorOrder(rightHandSides, w);
      krylov.deflate(w);
      w.array().rowwise() /= krylov.mNorms(w).transpose().array().max(std::numeric_limits<double>::min());
    }
    Eigen::VectorXd scale = krylov.mNorms(w);
    krylov.appendTimes(w, krylov.orthonormalise(w, krylov.gram(w), scale, random), rightHandSides);
    const int checkEvery = ritzCheckInterval(n, pairs);
    ReorthogonalisationSchedule schedule;
    for (int block = 0;; ++block) {
      op.solveInFactorOrder(rightHandSides, w);  // M times the last block, from appendTimes()
      krylov.deflate(w);
      scale = krylov.mNorms(w);
      Eigen::MatrixXd product = krylov.orthogonaliseLocally(w, scale);
      if (schedule.due()) {
        const Eigen::Index reach = schedule.reach(krylov.size());
        KrylovBasis::FullPass pass = krylov.orthogonaliseFully(w, reach);
        DriftProfile drift = ReorthogonalisationSchedule::profile(pass.columnDrift);
        if (ReorthogonalisationSchedule::cutShort(drift, reach, krylov.size(), kLanczosBlock)) {
          pass = krylov.orthogonaliseFully(w, krylov.size());
          drift = ReorthogonalisationSchedule::profile(pass.columnDrift);
        }
        schedule.record(drift);
        product = std::move(pass.gram);
      } else {
        schedule.recordSkipped();
      }
      const KrylovBasis::Orthonormalised next = krylov.orthonormalise(w, product, scale, random);
      const Eigen::MatrixXd& coupling = next.coupling;
      const bool full = krylov.size() + kLanczosBlock > krylov.capacity();
      if (krylov.size() >= least && (block % checkEvery == 0 || full)) {
        const RitzCheck check = checkRitzPairs(krylov, coupling, pairs, options.tolerance);
        if (check.converged)
          return convergedPairs(check, std::move(krylov), order, op.solveThreads(), sigma, op.solveCount());
      }
      if (full)
        return failure(BasisStatus::NotConverged,
                       "block Lanczos did not converge in " + std::to_string(krylov.size()) + " columns", op);
      krylov.appendTimes(w, next, rightHandSides);
    }
  } catch (const SolveCancelled&) {
    return failure(BasisStatus::Cancelled, "cancelled", op);
  } catch (const BasisExhausted&) {
    return failure(BasisStatus::NotConverged, "block Lanczos could not extend its basis", op);
  } catch (const std::runtime_error& e) {
    return failure(BasisStatus::FactorizationFailed, e.what(), op);
  }
}

BasisResult nearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                         const BasisOptions& options, bool* singleVector) {
  if (singleVector != nullptr) *singleVector = false;
  if (options.blockLanczos) {
    BasisResult result = blockLanczosNearestPairs(op, mass, pairs, 4 * pairs + 40, sigma, options);
    if (result.status != BasisStatus::NotConverged) return result;
  }
  if (singleVector != nullptr) *singleVector = true;
  return lanczosNearestPairs(op, mass, pairs, std::max(5 * pairs / 2, pairs + 20), sigma, options);
}

}  // namespace sc::spectral::detail
