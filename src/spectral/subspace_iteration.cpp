#include "spectral/subspace_iteration.h"

#include "spectral/parallel_ranges.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <thread>
#include <utility>

namespace sc::spectral::detail {
namespace {

using Status = SubspaceIterationResult::Status;
using Block = Eigen::Block<Eigen::MatrixXd, Eigen::Dynamic, Eigen::Dynamic, true>;
constexpr int kMaxDegree = 8;  ///< solves per sweep at most
/// Right-hand sides per CHOLMOD solve. CHOLMOD's simplicial solve sweeps L once for up to 4 right-hand sides, so
/// blocks of 4 read the factor a quarter as often. Measured on the 100k dragon (thread CPU time, one BLAS thread):
/// 3.6 ms per right-hand side in blocks of 4, 7.4 ms one at a time; the supernodal solve (many tiny BLAS calls on
/// a mesh's small supernodes) took 4.6–7.4 ms in blocks of 16.
constexpr Eigen::Index kSolveChunk = 4;

/// A simplicial Cholesky factor LLᵀ of S − σM whose solves may run on several threads at once.
class SharedFactor : public Eigen::CholmodSimplicialLLT<SparseMatrix, Eigen::Lower> {
 public:
  /// X ← (S − σM)⁻¹ X in chunks of kSolveChunk columns spread over `threads` threads. CHOLMOD is thread-safe when
  /// every thread has its own cholmod_common (its workspace), and a solve only reads the factor. False if a solve
  /// failed (out of memory).
  bool solveInPlace(Block X, int threads) const {
    const Eigen::Index chunks = (X.cols() + kSolveChunk - 1) / kSolveChunk;
    std::atomic<bool> ok{true};
    parallelRanges(chunks, threads, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
      cholmod_common common;
      cholmod_start(&common);
      Eigen::MatrixXd rhs;
      for (std::ptrdiff_t chunk = begin; chunk < end && ok; ++chunk) {
        const Eigen::Index c = chunk * kSolveChunk;
        const Eigen::Index w = std::min(kSolveChunk, X.cols() - c);
        rhs = X.middleCols(c, w);
        cholmod_dense B = Eigen::viewAsCholmod(rhs);
        cholmod_dense* solved = cholmod_solve(CHOLMOD_A, m_cholmodFactor, &B, &common);
        if (solved == nullptr) {
          ok = false;
          break;
        }
        X.middleCols(c, w) = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(solved->x), X.rows(), w);
        cholmod_free_dense(&solved, &common);
      }
      cholmod_finish(&common);
    });
    return ok;
  }
};

/// The buffers of one run, allocated once: a fresh #V×b temporary per step costs page faults (glibc maps blocks
/// this large with mmap and unmaps them on free) that measured about a quarter of the run time.
struct Workspace {
  Eigen::MatrixXd Y, SY, W, previous;  ///< #V by b: the block, S·block, scratch, the Chebyshev recursion's Y_{k−1}
  Eigen::MatrixXd locked;              ///< #V by m: the locked vectors
  Eigen::VectorXd sqrtMass, inverseMass;
};

/// X ← X − L(LᵀMX) for the l locked vectors L (M-orthonormal): M-orthogonal to them. `scratch` (#V by a, like X)
/// is overwritten.
void deflate(Block X, const Workspace& ws, Eigen::Index l, const Eigen::VectorXd& mass, Block scratch) {
  if (l == 0) return;
  scratch.noalias() = mass.asDiagonal() * X;
  const Eigen::MatrixXd C = ws.locked.leftCols(l).transpose() * scratch;
  X.noalias() -= ws.locked.leftCols(l) * C;
}

/// W = A·X = (S − σM)⁻¹ M X, then M-orthogonalised against the l locked vectors. X, W and scratch distinct,
/// #V by a.
bool applyA(const SharedFactor& factor, const Eigen::VectorXd& mass, const Workspace& ws, Eigen::Index l,
            const Block& X, Block W, Block scratch, int threads) {
  W.noalias() = mass.asDiagonal() * X;
  if (!factor.solveInPlace(W, threads)) return false;
  deflate(W, ws, l, mass, scratch);
  return true;
}

/// Rayleigh–Ritz on the columns of Y (SY = S·Y): θ ascending and Q (a by a) with (YQ)ᵀM(YQ) = I and
/// (YQ)ᵀS(YQ) = diag(θ). The Gram matrix is scaled to unit diagonal first (Jacobi), which removes the column-norm
/// part of its condition. `scratch` (#V by a) is overwritten.
bool rayleighRitz(const Block& Y, const Block& SY, const Eigen::VectorXd& sqrtMass, Block scratch,
                  Eigen::VectorXd& theta, Eigen::MatrixXd& Q) {
  scratch.noalias() = sqrtMass.asDiagonal() * Y;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(Y.cols(), Y.cols());
  G.selfadjointView<Eigen::Lower>().rankUpdate(scratch.transpose());
  G = G.selfadjointView<Eigen::Lower>();
  Eigen::MatrixXd T = Y.transpose() * SY;
  const Eigen::VectorXd scale = G.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  G = scale.asDiagonal() * G * scale.asDiagonal();
  T = scale.asDiagonal() * T * scale.asDiagonal();
  T = 0.5 * (T + T.transpose()).eval();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(T, G, Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
  if (eig.info() != Eigen::Success) return false;
  theta = eig.eigenvalues();
  Q = scale.asDiagonal() * eig.eigenvectors();
  return theta.allFinite() && Q.allFinite();
}

/// X ← X·Q and SX ← SX·Q in place through `scratch` (all #V by a).
void rotate(Block X, Block SX, const Eigen::MatrixXd& Q, Block scratch) {
  scratch.noalias() = X * Q;
  X = scratch;
  scratch.noalias() = SX * Q;
  SX = scratch;
}

Eigen::VectorXd residualsOf(const Block& SX, const Block& X, const Eigen::VectorXd& mass,
                            const Eigen::VectorXd& inverseMass, const Eigen::VectorXd& theta, double sigma) {
  Eigen::VectorXd r(theta.size());
  for (Eigen::Index k = 0; k < theta.size(); ++k)
    r(k) = std::sqrt((SX.col(k) - theta(k) * mass.cwiseProduct(X.col(k))).cwiseAbs2().dot(inverseMass)) /
           (std::abs(theta(k)) + std::abs(sigma));
  return r;
}

/// Drops the first k of the a columns of X (shifting the others left, in place).
void dropLeading(Eigen::MatrixXd& X, Eigen::Index a, Eigen::Index k) {
  for (Eigen::Index j = 0; j + k < a; ++j) X.col(j) = X.col(j + k);
}

}  // namespace

Eigen::VectorXd relativeResiduals(const Eigen::MatrixXd& Sx, const Eigen::MatrixXd& Mx, const Eigen::VectorXd& mass,
                                  const Eigen::VectorXd& theta, double sigma) {
  Eigen::VectorXd r(theta.size());
  const Eigen::VectorXd inverseMass = mass.cwiseInverse();
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const Eigen::VectorXd residual = Sx.col(k) - theta(k) * Mx.col(k);
    r(k) = std::sqrt(residual.cwiseAbs2().dot(inverseMass)) / (std::abs(theta(k)) + std::abs(sigma));
  }
  return r;
}

SubspaceIterationResult subspaceIteration(const LaplaceOperators& ops, double sigma, Eigen::MatrixXd start,
                                          const SubspaceIterationOptions& options) {
  SubspaceIterationResult result;
  const Eigen::Index n = ops.mass.size();
  const Eigen::Index m = options.wanted;
  const Eigen::Index b = start.cols();
  if (m < 1 || b <= m || start.rows() != n) return result;

  // === step 1: one simplicial factor of S − σM (block solves of kSolveChunk right-hand sides)
  SharedFactor factor;
  {
    SparseMatrix shiftedMass(n, n);
    shiftedMass.setIdentity();
    shiftedMass.diagonal() = -sigma * ops.mass;
    factor.compute(ops.stiffness + shiftedMass);
  }
  if (factor.info() != Eigen::Success) {
    result.status = Status::FactorizationFailed;
    return result;
  }

  // === step 2: sweeps of (solve^d, deflate locked, Rayleigh–Ritz, lock)
  Workspace ws;
  ws.Y = std::move(start);
  ws.SY.resize(n, b);
  ws.W.resize(n, b);
  ws.previous.resize(n, b);
  ws.locked.resize(n, m);
  ws.sqrtMass = ops.mass.cwiseSqrt();
  ws.inverseMass = ops.mass.cwiseInverse();
  Eigen::VectorXd lockedValues(m);
  Eigen::Index l = 0;
  Eigen::Index a = b;  ///< active columns: ws.Y.leftCols(a)
  int degree = 1;
  double cut = 0.0;  ///< c: A's spectrum beyond the block lies in [0, c]; 0 until the first Rayleigh–Ritz
  Eigen::VectorXd theta;
  Eigen::MatrixXd Q;
  while (l < m && result.sweeps < options.maxSweeps) {
    // Chebyshev filter of degree d in A on [0, c], c = 1/(θ_top − σ) (the unwanted part of A's spectrum, beyond
    // the block): Y_{k+1} = 2((2/c)AY_k − Y_k) − Y_{k−1}. Plain A on the first sweep (no Ritz values yet).
    // Each application is followed by M-orthogonalisation against the locked pairs: A amplifies their directions
    // most (smallest λ), and a degree-d filter would otherwise blow their residual leak up to round-off garbage.
    auto Y = [&] { return ws.Y.leftCols(a); };
    auto W = [&] { return ws.W.leftCols(a); };
    const int threads = options.threads > 0 ? options.threads
                                            : static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u));
    bool solved = applyA(factor, ops.mass, ws, l, Y(), W(), ws.SY.leftCols(a), threads);
    result.solves += static_cast<int>(a) * (cut <= 0.0 ? 1 : degree);
    if (cut > 0.0) {
      W() = (2.0 / cut) * W() - Y();
      for (int k = 1; k < degree && solved; ++k) {
        ws.previous.swap(ws.Y);  // previous = Y_{k−1}
        ws.Y.swap(ws.W);         // Y = Y_k
        solved = applyA(factor, ops.mass, ws, l, Y(), W(), ws.SY.leftCols(a), threads);
        W() = 2.0 * ((2.0 / cut) * W() - Y()) - ws.previous.leftCols(a);
      }
    }
    if (!solved) break;  // out of memory in CHOLMOD: NotConverged
    ws.Y.swap(ws.W);
    for (int pass = 0; pass < 2; ++pass) deflate(Y(), ws, l, ops.mass, ws.SY.leftCols(a));
    ws.SY.leftCols(a).noalias() = ops.stiffness * Y();
    if (!rayleighRitz(Y(), ws.SY.leftCols(a), ws.sqrtMass, W(), theta, Q)) break;
    rotate(Y(), ws.SY.leftCols(a), Q, W());
    const Eigen::VectorXd r = residualsOf(ws.SY.leftCols(a), Y(), ops.mass, ws.inverseMass, theta, sigma);
    ++result.sweeps;

    Eigen::Index k = 0;
    while (k < a && l + k < m && r(k) <= options.tolerance) ++k;
    ws.locked.middleCols(l, k) = Y().leftCols(k);
    lockedValues.segment(l, k) = theta.head(k);
    l += k;
    if (options.progress && !options.progress(static_cast<double>(l) / static_cast<double>(m))) {
      result.status = Status::Cancelled;
      return result;
    }
    if (l == m) {
      result.guard = Y().rightCols(a - k);
      break;
    }
    dropLeading(ws.Y, a, k);
    dropLeading(ws.SY, a, k);
    a -= k;
    theta = theta.tail(a).eval();
    // The highest degree that keeps the Gram matrix of the filtered block below maxGramCondition. Column scaling
    // removes each column's own growth T_d(x_i); what remains is the leak of a strongly amplified pair into the
    // other columns, about r_i·T_d(x_i) (r_i its residual, x_i = 2(θ_top − σ)/(θ_i − σ) − 1 ≥ 1).
    cut = 1.0 / (theta(a - 1) - sigma);
    // No higher than needed either: a wanted pair's residual shrinks by about T_d(x_i) per filter (its unwanted
    // components stay at most 1), so stop at the degree that brings every wanted pair below half the tolerance.
    const Eigen::VectorXd residual = r.tail(a);
    const Eigen::Index wantedActive = m - l;
    auto chebyshev = [&](int d, Eigen::Index i) {
      const double x = std::max(1.0, 2.0 * (theta(a - 1) - sigma) / (theta(i) - sigma) - 1.0);
      return std::cosh(d * std::acosh(x));
    };
    auto growth = [&](int d) {
      double worst = 0.0;
      for (Eigen::Index i = 0; i < a; ++i) worst = std::max(worst, (residual(i) + 1e-8) * chebyshev(d, i));
      return worst;
    };
    auto converges = [&](int d) {
      for (Eigen::Index i = 0; i < wantedActive; ++i)
        if (residual(i) / chebyshev(d, i) > 0.5 * options.tolerance) return false;
      return true;
    };
    degree = 1;
    while (degree < kMaxDegree && !converges(degree) && growth(degree + 1) <= std::sqrt(options.maxGramCondition))
      ++degree;
  }
  if (l < m) return result;

  // === step 3: a last Rayleigh–Ritz on the locked vectors (M-orthonormal to round-off), residuals reported
  auto X = ws.locked.leftCols(m);
  ws.SY.leftCols(m).noalias() = ops.stiffness * X;
  if (!rayleighRitz(X, ws.SY.leftCols(m), ws.sqrtMass, ws.W.leftCols(m), theta, Q)) return result;
  rotate(X, ws.SY.leftCols(m), Q, ws.W.leftCols(m));
  result.eigenvalues = theta;
  result.residuals = residualsOf(ws.SY.leftCols(m), X, ops.mass, ws.inverseMass, theta, sigma);
  result.vectors = std::move(ws.locked);  // #V by m exactly: no copy at the peak
  result.status = Status::Converged;
  return result;
}

}  // namespace sc::spectral::detail
