#include "spectral/shift_invert_operator.h"

#include "spectral/huge_pages.h"
#include "spectral/parallel_ranges.h"
#include "spectral/up_looking_ldlt.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace sc::spectral::detail {
namespace {

/// CHOLMOD's allocations, advised onto huge pages from 4 MiB up (its factor: 150 MB at 437k vertices; each solve's
/// right-hand sides and result).
constexpr std::size_t kHugeBuffer = std::size_t{4} << 20;

void* adviseLarge(void* data, std::size_t bytes) {
  if (data != nullptr && bytes >= kHugeBuffer) adviseHugePages(data, bytes);
  return data;
}
void* cholmodMalloc(std::size_t bytes) { return adviseLarge(std::malloc(bytes), bytes); }
void* cholmodCalloc(std::size_t count, std::size_t size) { return adviseLarge(std::calloc(count, size), count * size); }
void* cholmodRealloc(void* data, std::size_t bytes) { return adviseLarge(std::realloc(data, bytes), bytes); }

/// Points SuiteSparse's allocator at the functions above, once per process (CHOLMOD reads SuiteSparse_config on
/// every allocation; src/spectral is its only user). Freeing stays std::free.
void adviseCholmodOntoHugePages() {
  static std::once_flag once;
  std::call_once(once, [] {
    SuiteSparse_config.malloc_func = cholmodMalloc;
    SuiteSparse_config.calloc_func = cholmodCalloc;
    SuiteSparse_config.realloc_func = cholmodRealloc;
  });
}

/// `shifted` = S − σ·M with S's pattern, in arrays advised onto huge pages: S copied and σ·m subtracted from each
/// diagonal entry, the values Eigen's S + (−σ·M) gives, without that sum's growing temporary (its reallocations and
/// page faults: 8,800 of the 437k basis run's 63,000). Where S lacks a diagonal entry (a vertex no face uses), that
/// sum. Cost: O(nnz). (An out-parameter: returning it by value could copy it, Eigen 3.4 having no sparse move.)
void shiftedStiffness(const SparseMatrix& S, const Eigen::VectorXd& mass, double sigma, SparseMatrix& shifted) {
  const Eigen::Index n = S.cols();
  std::vector<int> diagonalAt(static_cast<std::size_t>(n));
  bool everyDiagonal = S.isCompressed();
  for (Eigen::Index c = 0; c < n && everyDiagonal; ++c) {
    const int* begin = S.innerIndexPtr() + S.outerIndexPtr()[c];
    const int* end = S.innerIndexPtr() + S.outerIndexPtr()[c + 1];
    const int* at = std::lower_bound(begin, end, static_cast<int>(c));
    everyDiagonal = at != end && *at == c;
    diagonalAt[static_cast<std::size_t>(c)] = static_cast<int>(at - S.innerIndexPtr());
  }
  if (!everyDiagonal) {
    SparseMatrix shiftedMass(S.rows(), S.cols());
    shiftedMass.setIdentity();
    shiftedMass.diagonal() = -sigma * mass;
    shifted = S + shiftedMass;
    return;
  }
  const auto nonZeros = static_cast<std::size_t>(S.nonZeros());
  shifted.resize(n, n);
  std::copy(S.outerIndexPtr(), S.outerIndexPtr() + n + 1, shifted.outerIndexPtr());
  shifted.resizeNonZeros(static_cast<Eigen::Index>(nonZeros));
  adviseHugePages(shifted.innerIndexPtr(), nonZeros * sizeof(int));
  adviseHugePages(shifted.valuePtr(), nonZeros * sizeof(double));
  std::copy(S.innerIndexPtr(), S.innerIndexPtr() + nonZeros, shifted.innerIndexPtr());
  std::copy(S.valuePtr(), S.valuePtr() + nonZeros, shifted.valuePtr());
  double* values = shifted.valuePtr();
  for (Eigen::Index c = 0; c < n; ++c) values[diagonalAt[static_cast<std::size_t>(c)]] += -sigma * mass(c);
}

}  // namespace

void InertiaLdlt::factorizeOnThreads(const SparseMatrix& a, int threads) {
  eigen_assert(m_analysisIsOk && "analyzePattern() first");
  if (!factorUpLooking(a, *m_cholmodFactor, threads, cholmod())) {
    factorize(a);
    return;
  }
  m_info = m_cholmodFactor->minor == m_cholmodFactor->n ? Eigen::Success : Eigen::NumericalIssue;
  m_factorizationIsOk = true;
}

int InertiaLdlt::negativePivots() const {
  // A simplicial LDLᵀ factor keeps D on L's diagonal: the first entry of each column (cholmod_factor, is_ll false).
  const cholmod_factor& factor = *m_cholmodFactor;
  const auto* values = static_cast<const double*>(factor.x);
  const auto* columnStarts = static_cast<const int*>(factor.p);
  int negatives = 0;
  for (std::size_t column = 0; column < factor.n; ++column) negatives += values[columnStarts[column]] < 0.0 ? 1 : 0;
  return negatives;
}

std::span<const int> InertiaLdlt::order() const {
  const cholmod_factor& factor = *m_cholmodFactor;
  return {static_cast<const int*>(factor.Perm), factor.n};
}

void InertiaLdlt::solveColumns(const Eigen::MatrixXd& x, Eigen::MatrixXd& y, int threads) const {
  solveColumns(CHOLMOD_A, x, y, threads);
}

void InertiaLdlt::solveColumnsInOrder(const Eigen::MatrixXd& x, Eigen::MatrixXd& y, int threads) const {
  solveColumns(CHOLMOD_LDLt, x, y, threads);
}

void InertiaLdlt::solveColumns(int system, const Eigen::MatrixXd& x, Eigen::MatrixXd& y, int threads) const {
  y.resize(x.rows(), x.cols());
  std::atomic<bool> failed{false};
  parallelRanges(x.cols(), threads, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    cholmod_common common;
    cholmod_start(&common);
    const auto view = [&x](const double* data, std::ptrdiff_t columns) {
      cholmod_dense dense{};
      dense.nrow = static_cast<std::size_t>(x.rows());
      dense.ncol = static_cast<std::size_t>(columns);
      dense.nzmax = dense.nrow * dense.ncol;
      dense.d = dense.nrow;
      dense.x = const_cast<double*>(data);  // cholmod_solve2 reads B only
      dense.xtype = CHOLMOD_REAL;
      dense.dtype = CHOLMOD_DOUBLE;
      return dense;
    };
    cholmod_dense columns = view(x.col(begin).data(), end - begin);
    // The solution is written straight into Y's columns: cholmod_solve2 keeps an X of the right size and type
    // (cholmod_ensure_dense) rather than allocating one, which would cost a copy of every solved column.
    cholmod_dense into = view(y.col(begin).data(), end - begin);
    cholmod_dense* solved = &into;
    cholmod_dense* workspace = nullptr;
    cholmod_dense* entries = nullptr;
    if (!cholmod_solve2(system, m_cholmodFactor, &columns, nullptr, &solved, nullptr, &workspace, &entries, &common))
      failed = true;
    cholmod_free_dense(&workspace, &common);
    cholmod_free_dense(&entries, &common);
    cholmod_finish(&common);
  });
  if (failed) throw std::runtime_error("CHOLMOD's solve failed (out of memory)");
}

ShiftInvertOperator::ShiftInvertOperator(const SparseMatrix& S, const Eigen::VectorXd& mass,
                                         std::function<bool(int)> observer)
    : m_S(S), m_mass(mass), m_observer(std::move(observer)) {
  adviseCholmodOntoHugePages();
}

void ShiftInvertOperator::set_shift(const double& sigma) {
  if (m_factored && sigma == m_sigma) return;
  m_factored = false;
  m_subtrees.reset();
  m_subtreesFor = 0;
  SparseMatrix shifted;
  shiftedStiffness(m_S, m_mass, sigma, shifted);
  if (!m_analysed) {
    m_factor.analyzePattern(shifted);
    m_analysed = true;
  }
  m_factor.factorizeOnThreads(shifted, m_solveThreads);
  if (m_factor.info() != Eigen::Success)
    throw std::runtime_error("LDL' factorisation of S - sigma*M failed (a zero pivot: sigma is an eigenvalue)");
  if (sigma < 0.0 && m_factor.negativePivots() > 0)
    throw std::runtime_error("S - sigma*M is not positive definite for sigma < 0 (S not PSD or M singular)");
  m_sigma = sigma;
  m_factored = true;
}

void ShiftInvertOperator::perform_op(const double* x, double* y) const {
  Eigen::Map<Eigen::VectorXd>(y, rows()) = m_factor.solve(Eigen::Map<const Eigen::VectorXd>(x, rows()));
  ++m_solves;
  if (m_observer && !m_observer(m_solves)) throw SolveCancelled{};
}

void ShiftInvertOperator::solve(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const {
  if (m_solveThreads > 1 && x.cols() > 1)
    m_factor.solveColumns(x, y, m_solveThreads);
  else
    y = m_factor.solve(x);
  countSolves(x.cols());
}

void ShiftInvertOperator::solveInFactorOrder(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const {
  if (m_subtreesFor != m_solveThreads) {
    m_subtrees = SubtreeLdltSolve::split(m_factor.factor(), m_solveThreads);
    m_subtreesFor = m_solveThreads;
  }
  if (m_subtrees)
    m_subtrees->solve(x, y);
  else
    m_factor.solveColumnsInOrder(x, y, m_solveThreads);
  countSolves(x.cols());
}

void ShiftInvertOperator::countSolves(Eigen::Index columns) const {
  for (Eigen::Index column = 0; column < columns; ++column) {
    ++m_solves;
    if (m_observer && !m_observer(m_solves)) throw SolveCancelled{};
  }
}

void DiagonalMassOperator::perform_op(const double* x, double* y) const {
  Eigen::Map<Eigen::VectorXd>(y, rows()) = m_mass.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(x, rows()));
}

}  // namespace sc::spectral::detail
