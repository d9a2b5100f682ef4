#pragma once
// KrylovBasis: the M-orthonormal Krylov basis of a block shift-invert Lanczos run and its projected matrix, with the
// sweeps that keep it orthonormal. Internal to src/spectral (block_lanczos.cpp).

#include "spectral/lanczos_block.h"

#include <Eigen/Core>

#include <optional>
#include <random>

namespace sc::spectral::detail {

/// A column whose M-norm after orthogonalisation is below this fraction of its norm before lies in the span of the
/// earlier ones (the Krylov space is exhausted in that direction): it is replaced by a random direction.
inline constexpr double kDeflation = 1e-10;
/// Cholesky QR is used for a block whose every column keeps at least this fraction of its length after the
/// earlier ones are removed (its Gram matrix's condition number then stays below 10⁸, which two passes make exact).
inline constexpr double kCholeskyConditioning = 1e-4;
/// Thrown when a block cannot be completed to an M-orthonormal one (only on tiny meshes); reported NotConverged.
struct BasisExhausted {};
/// orthogonaliseFully() repeats its pass for a column that pass shortened below this fraction of its length.
inline constexpr double kSecondPass = 0.5;

/// The Krylov basis Q (M-orthonormal columns) and the projected matrix T = QᵀM(S − σM)⁻¹MQ built block by block.
class KrylovBasis {
 public:
  /// `threads`: the row-band sweeps (local orthogonalisation, Cholesky QR, full passes, deflation) and the Ritz
  /// vectors' bands run on this many threads.
  /// `deflation`: M-orthonormal columns every vector of the basis is kept M-orthogonal to (nullptr: none).
  KrylovBasis(const Eigen::VectorXd& mass, Eigen::Index capacity, int threads, const Eigen::MatrixXd* deflation);

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
  Eigen::MatrixXd orthogonaliseLocally(Eigen::MatrixXd& w, Eigen::VectorXd lengths);

  /// Removes the deflation columns X from W (twice: W −= X·XᵀMW), so that the operator acts on X's M-orthogonal
  /// complement, where its eigenpairs are the others. Nothing without deflation. Cost: four reads of X.
  void deflate(Eigen::MatrixXd& w) const;

  /// WᵀMW. Cost: one sweep over W.
  Eigen::MatrixXd gram(const Eigen::MatrixXd& w) const;

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
  FullPass orthogonaliseFully(Eigen::MatrixXd& w, Eigen::Index reach) const;

  /// The M-norm of each column of W. Cost: O(#V·cols).
  Eigen::VectorXd mNorms(const Eigen::MatrixXd& w) const;

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
                                 std::mt19937& random);

  /// W = W_new·R by Cholesky QR in the M inner product, twice (the second pass restores the orthonormality the first
  /// loses to W's conditioning), R upper triangular; or nullopt, W untouched, when a column is within a factor
  /// kCholeskyConditioning of the span of the others or below the deflation threshold: orthonormalise() then takes
  /// the column-by-column route. The first pass is applied to W; the second is returned as `pending` (R₂⁻¹), which
  /// appendTimes() applies as it writes the block into the basis. Cost: one sweep over W (the first Gram matrix is
  /// the caller's).
  std::optional<Orthonormalised> choleskyQr(Eigen::MatrixXd& w, const Eigen::MatrixXd& product,
                                            const Eigen::VectorXd& scale) const;

  /// Q·C for C of size() rows and at most size() columns, computed in place in Q's leading columns one band of rows
  /// at a time (each band of Q·C needs only that band of Q; the bands are split over the basis's threads), then Q
  /// shrunk to them: the Ritz vectors cost no second #V × pairs matrix (800 MB at 1M vertices and m = 100). Leaves
  /// the basis empty. Cost: O(#V·size()·C.cols()).
  Eigen::MatrixXd ritzVectors(const Eigen::MatrixXd& coordinates) &&;

  /// Appends the M-orthonormal block W·block.pending, and sets `rightHandSides` to M times it (the next solve's),
  /// in one sweep; its coupling goes below the previous block in T. Requires room for a block (size() < capacity()).
  void appendTimes(const Eigen::MatrixXd& w, const Orthonormalised& block, Eigen::MatrixXd& rightHandSides);

 private:
  const Eigen::VectorXd& m_mass;
  Eigen::MatrixXd m_q;
  Eigen::MatrixXd m_t;
  Eigen::Index m_size = 0;
  int m_threads = 1;
  const Eigen::MatrixXd* m_deflation = nullptr;
};

}  // namespace sc::spectral::detail
