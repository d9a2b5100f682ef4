#include "spectral/block_lanczos.h"

#include "spectral/banded_products.h"
#include "spectral/huge_pages.h"
#include "spectral/lanczos_solver.h"
#include "spectral/parallel_ranges.h"
#include "spectral/reorthogonalisation_schedule.h"
#include "spectral/vertex_order.h"

#include <Eigen/Cholesky>
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

/// A column whose M-norm after orthogonalisation is below this fraction of its norm before lies in the span of the
/// earlier ones (the Krylov space is exhausted in that direction): it is replaced by a random direction.
constexpr double kDeflation = 1e-10;
constexpr unsigned kSeed = 0x5eed;
/// Applications of the operator to the random start block before it becomes the first Krylov block.
constexpr int kStartSmoothing = 2;

/// Cholesky QR is used for a block whose every column keeps at least this fraction of its length after the
/// earlier ones are removed (its Gram matrix's condition number then stays below 10⁸, which two passes make exact).
constexpr double kCholeskyConditioning = 1e-4;
/// Thrown when a block cannot be completed to an M-orthonormal one (only on tiny meshes); reported NotConverged.
struct BasisExhausted {};
/// orthogonaliseFully() repeats its pass for a column that pass shortened below this fraction of its length.
constexpr double kSecondPass = 0.5;

/// The Krylov basis Q (M-orthonormal columns) and the projected matrix T = QᵀM(S − σM)⁻¹MQ built block by block.
class KrylovBasis {
 public:
  /// `threads`: the row-band sweeps (local orthogonalisation, Cholesky QR, full passes, deflation) and the Ritz
  /// vectors' bands run on this many threads.
  /// `deflation`: M-orthonormal columns every vector of the basis is kept M-orthogonal to (nullptr: none).
  KrylovBasis(const Eigen::VectorXd& mass, Eigen::Index capacity, int threads, const Eigen::MatrixXd* deflation)
      : m_mass(mass),
        m_q(mass.size(), capacity),
        m_t(Eigen::MatrixXd::Zero(capacity, capacity)),
        m_threads(threads),
        m_deflation(deflation) {
    adviseHugePages(m_q.data(), static_cast<std::size_t>(m_q.size()) * sizeof(double));  // before any first write
  }

  Eigen::Index size() const { return m_size; }
  Eigen::Index capacity() const { return m_q.cols(); }
  /// Writes zeros into the first `columns` columns (at most capacity()), so that later writes find their pages
  /// mapped. Safe on another thread before any other member is called.
  void touch(Eigen::Index columns) { m_q.leftCols(std::min(columns, capacity())).setZero(); }
  auto columns() const { return m_q.leftCols(m_size); }
  const Eigen::MatrixXd& projected() const { return m_t; }

  /// Makes W orthogonal to the last two blocks (the block three-term recurrence), with a second pass for a column the
  /// first shortened below kSecondPass of its length (`lengths`: W's column M-norms on entry); records the
  /// coefficients, A_j and B_{j−1}ᵀ, in T's column block of the last block. Returns W's new Gram matrix WᵀMW.
  /// Cost: two or three sweeps over W and the last two blocks (banded_products.h: each subtraction measures what it
  /// leaves, which the second pass subtracts without a projection sweep of its own).
  Eigen::MatrixXd orthogonaliseLocally(Eigen::MatrixXd& w, Eigen::VectorXd lengths) {
    const Eigen::Index local = std::min<Eigen::Index>(m_size, 2 * kLanczosBlock);
    if (local == 0) return gram(w);
    const auto recent = m_q.middleCols(m_size - local, local);
    Eigen::MatrixXd total = Eigen::MatrixXd::Zero(local, w.cols());
    Eigen::MatrixXd h = massProjection(recent, m_mass, w, m_threads);
    Eigen::MatrixXd product;
    for (int pass = 0; pass < 2; ++pass) {
      SubtractedBlock subtracted = subtractWithGramAndProjection(w, recent, h, m_mass, m_threads);
      product = std::move(subtracted.gram);
      total += h;
      const Eigen::VectorXd after = product.diagonal().cwiseMax(0.0).cwiseSqrt();
      if ((after.array() >= kSecondPass * lengths.array()).all()) break;
      lengths = after;
      h = std::move(subtracted.projection);  // what the first pass left, measured in its own sweep
    }
    m_t.block(m_size - local, m_size - kLanczosBlock, local, kLanczosBlock) = total;
    return product;
  }

  /// Removes the deflation columns X from W (twice: W −= X·XᵀMW), so that the operator acts on X's M-orthogonal
  /// complement, where its eigenpairs are the others. Nothing without deflation. Cost: four reads of X.
  void deflate(Eigen::MatrixXd& w) const {
    if (m_deflation == nullptr || m_deflation->cols() == 0) return;
    for (int pass = 0; pass < 2; ++pass)
      subtractWithGram(w, *m_deflation, massProjection(*m_deflation, m_mass, w, m_threads), m_mass, m_threads);
  }

  /// WᵀMW. Cost: one sweep over W.
  Eigen::MatrixXd gram(const Eigen::MatrixXd& w) const { return massGram(w, m_mass, m_threads); }

  /// What a full pass removed and left: each covered column's drift (max |q_kᵀ M w|/‖w‖_M over W's columns, before
  /// the pass) and W's new Gram matrix WᵀMW.
  struct FullPass {
    Eigen::VectorXd columnDrift;
    Eigen::MatrixXd gram;
  };

  /// Makes W orthogonal to the first `reach` columns (at most size()): one pass (two sweeps over bands of rows of
  /// those columns, banded_products.h, on the basis's threads), and a second for a column the first shortened below
  /// kSecondPass of its length (Daniel–Gragg–Kaufman–Stewart's criterion: only then has cancellation left it less
  /// orthogonal than round-off). The coefficients are not recorded: T stays the block tridiagonal matrix of the
  /// recurrence, which is what semi-orthogonality keeps accurate. Cost: two reads of the covered columns per pass,
  /// O(#V·reach).
  FullPass orthogonaliseFully(Eigen::MatrixXd& w, Eigen::Index reach) const {
    FullPass result;
    reach = std::min(reach, m_size);
    const auto covered = m_q.leftCols(reach);
    Eigen::VectorXd before = mNorms(w);
    for (int pass = 0; pass < 2 && reach > 0; ++pass) {
      const Eigen::MatrixXd h = massProjection(covered, m_mass, w, m_threads);
      result.gram = subtractWithGram(w, covered, h, m_mass, m_threads);
      if (pass == 0)
        result.columnDrift =
            (h.cwiseAbs().array().rowwise() / before.transpose().array().max(std::numeric_limits<double>::min()))
                .rowwise()
                .maxCoeff();
      const Eigen::VectorXd after = result.gram.diagonal().cwiseMax(0.0).cwiseSqrt();
      if ((after.array() >= kSecondPass * before.array()).all()) break;
      before = after;
    }
    if (reach == 0) result.gram = gram(w);
    return result;
  }

  /// The M-norm of each column of W. Cost: O(#V·cols).
  Eigen::VectorXd mNorms(const Eigen::MatrixXd& w) const {
    return (w.array().square().colwise() * m_mass.array()).colwise().sum().transpose().cwiseMax(0.0).cwiseSqrt();
  }

  /// An orthonormalised block: W·pending is M-orthonormal (the last Cholesky QR pass, applied by appendTimes() as it
  /// writes the block into the basis), and coupling = (W·pending)ᵀ M W_old, the coupling to the last block.
  struct Orthonormalised {
    Eigen::MatrixXd coupling;
    Eigen::MatrixXd pending;
  };

  /// Makes W (already orthogonal to Q; `product` = WᵀMW) M-orthonormal but for the returned `pending` factor: by
  /// choleskyQr() when its columns are well apart, else column by column (Gram–Schmidt twice within the block; then
  /// pending = I), where a column that vanishes is replaced by a random one orthogonalised against Q and the block.
  /// `scale`: the columns' norms before orthogonalisation against Q.
  Orthonormalised orthonormalise(Eigen::MatrixXd& w, const Eigen::MatrixXd& product, Eigen::VectorXd& scale,
                                 std::mt19937& random) {
    if (std::optional<Orthonormalised> done = choleskyQr(w, product, scale)) return *std::move(done);
    const Eigen::MatrixXd original = w;
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (Eigen::Index c = 0; c < w.cols(); ++c) {
      for (int attempt = 0;; ++attempt) {
        for (int pass = 0; pass < 2; ++pass) {
          for (Eigen::Index p = 0; p < c; ++p) w.col(c) -= w.col(p).dot(m_mass.cwiseProduct(w.col(c))) * w.col(p);
        }
        const double norm = std::sqrt(w.col(c).dot(m_mass.cwiseProduct(w.col(c))));
        if (norm > kDeflation * scale[c] && norm > 0.0) {
          w.col(c) /= norm;
          break;
        }
        if (attempt == 3) throw BasisExhausted{};
        Eigen::MatrixXd fresh = Eigen::MatrixXd::NullaryExpr(w.rows(), 1, [&] { return uniform(random); });
        deflate(fresh);
        orthogonaliseFully(fresh, m_size);
        w.col(c) = fresh;
        scale[c] = std::sqrt(fresh.col(0).dot(m_mass.cwiseProduct(fresh.col(0))));
      }
    }
    return {w.transpose() * (m_mass.asDiagonal() * original), Eigen::MatrixXd::Identity(w.cols(), w.cols())};
  }

  /// W = W_new·R by Cholesky QR in the M inner product, twice (the second pass restores the orthonormality the first
  /// loses to W's conditioning), R upper triangular; or nullopt, W untouched, when a column is within a factor
  /// kCholeskyConditioning of the span of the others or below the deflation threshold: orthonormalise() then takes
  /// the column-by-column route. The first pass is applied to W; the second is returned as `pending` (R₂⁻¹), which
  /// appendTimes() applies as it writes the block into the basis. Cost: one sweep over W (the first Gram matrix is
  /// the caller's).
  std::optional<Orthonormalised> choleskyQr(Eigen::MatrixXd& w, const Eigen::MatrixXd& product,
                                            const Eigen::VectorXd& scale) const {
    const Eigen::Index b = w.cols();
    Eigen::MatrixXd coupling = Eigen::MatrixXd::Identity(b, b);
    Eigen::MatrixXd g = product;
    for (int pass = 0; pass < 2; ++pass) {
      const Eigen::LLT<Eigen::MatrixXd> cholesky(g);
      if (cholesky.info() != Eigen::Success) {
        if (pass == 0) return std::nullopt;
        throw BasisExhausted{};  // not after a first pass that met the conditioning bound; W is changed by then
      }
      const Eigen::MatrixXd r = cholesky.matrixU();
      if (pass == 0) {
        for (Eigen::Index c = 0; c < b; ++c) {
          const double pivot = r(c, c);
          if (!(pivot > kCholeskyConditioning * std::sqrt(g(c, c))) || !(pivot > kDeflation * scale[c]))
            return std::nullopt;
        }
      }
      Eigen::MatrixXd inverse = r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
      coupling = r * coupling;
      if (pass == 1) return Orthonormalised{std::move(coupling), std::move(inverse)};
      g = multiplyWithGram(w, inverse, m_mass, m_threads);
    }
    return std::nullopt;  // not reached
  }

  /// Q·C for C of size() rows and at most size() columns, computed in place in Q's leading columns one band of rows
  /// at a time (each band of Q·C needs only that band of Q; the bands are split over the basis's threads), then Q
  /// shrunk to them: the Ritz vectors cost no second #V × pairs matrix (800 MB at 1M vertices and m = 100). Leaves
  /// the basis empty. Cost: O(#V·size()·C.cols()).
  Eigen::MatrixXd ritzVectors(const Eigen::MatrixXd& coordinates) && {
    constexpr Eigen::Index kBand = 2048;
    const Eigen::Index n = m_q.rows();
    const Eigen::Index k = coordinates.cols();
    const Eigen::Index bands = (n + kBand - 1) / kBand;
    parallelRanges(bands, m_threads, [&](std::ptrdiff_t first, std::ptrdiff_t last) {
      Eigen::MatrixXd band;
      for (Eigen::Index row = first * kBand; row < std::min(n, last * kBand); row += kBand) {
        const Eigen::Index rows = std::min(kBand, n - row);
        band.noalias() = m_q.block(row, 0, rows, m_size) * coordinates;
        m_q.block(row, 0, rows, k) = band;
      }
    });
    m_q.conservativeResize(n, k);  // column-major, same rows: a realloc that keeps the leading columns
    m_size = 0;
    return std::move(m_q);
  }

  /// Appends the M-orthonormal block W·block.pending, and sets `rightHandSides` to M times it (the next solve's),
  /// in one sweep; its coupling goes below the previous block in T. Requires room for a block (size() < capacity()).
  void appendTimes(const Eigen::MatrixXd& w, const Orthonormalised& block, Eigen::MatrixXd& rightHandSides) {
    multiplyInto(w, block.pending, m_mass, m_q.middleCols(m_size, kLanczosBlock), rightHandSides, m_threads);
    const Eigen::MatrixXd& coupling = block.coupling;
    if (m_size > 0) m_t.block(m_size, m_size - kLanczosBlock, kLanczosBlock, kLanczosBlock) = coupling;
    m_size += kLanczosBlock;
  }

 private:
  const Eigen::VectorXd& m_mass;
  Eigen::MatrixXd m_q;
  Eigen::MatrixXd m_t;
  Eigen::Index m_size = 0;
  int m_threads = 1;
  const Eigen::MatrixXd* m_deflation = nullptr;
};

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
