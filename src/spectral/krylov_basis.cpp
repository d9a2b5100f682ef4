#include "spectral/krylov_basis.h"

#include "spectral/banded_products.h"
#include "spectral/huge_pages.h"
#include "spectral/parallel_ranges.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace sc::spectral::detail {

KrylovBasis::KrylovBasis(const Eigen::VectorXd& mass, Eigen::Index capacity, int threads,
                         const Eigen::MatrixXd* deflation)
    : m_mass(mass),
      m_q(mass.size(), capacity),
      m_t(Eigen::MatrixXd::Zero(capacity, capacity)),
      m_threads(threads),
      m_deflation(deflation) {
  adviseHugePages(m_q.data(), static_cast<std::size_t>(m_q.size()) * sizeof(double));  // before any first write
}

Eigen::MatrixXd KrylovBasis::orthogonaliseLocally(Eigen::MatrixXd& w, Eigen::VectorXd lengths) {
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

Eigen::MatrixXd KrylovBasis::gram(const Eigen::MatrixXd& w) const { return massGram(w, m_mass, m_threads); }

void KrylovBasis::deflate(Eigen::MatrixXd& w) const {
  if (m_deflation == nullptr || m_deflation->cols() == 0) return;
  for (int pass = 0; pass < 2; ++pass)
    subtractWithGram(w, *m_deflation, massProjection(*m_deflation, m_mass, w, m_threads), m_mass, m_threads);
}

KrylovBasis::FullPass KrylovBasis::orthogonaliseFully(Eigen::MatrixXd& w, Eigen::Index reach) const {
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

Eigen::VectorXd KrylovBasis::mNorms(const Eigen::MatrixXd& w) const {
  return (w.array().square().colwise() * m_mass.array()).colwise().sum().transpose().cwiseMax(0.0).cwiseSqrt();
}

KrylovBasis::Orthonormalised KrylovBasis::orthonormalise(Eigen::MatrixXd& w, const Eigen::MatrixXd& product,
                                                         Eigen::VectorXd& scale, std::mt19937& random) {
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

std::optional<KrylovBasis::Orthonormalised> KrylovBasis::choleskyQr(Eigen::MatrixXd& w, const Eigen::MatrixXd& product,
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

Eigen::MatrixXd KrylovBasis::ritzVectors(const Eigen::MatrixXd& coordinates) && {
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

void KrylovBasis::appendTimes(const Eigen::MatrixXd& w, const Orthonormalised& block, Eigen::MatrixXd& rightHandSides) {
  multiplyInto(w, block.pending, m_mass, m_q.middleCols(m_size, kLanczosBlock), rightHandSides, m_threads);
  const Eigen::MatrixXd& coupling = block.coupling;
  if (m_size > 0) m_t.block(m_size, m_size - kLanczosBlock, kLanczosBlock, kLanczosBlock) = coupling;
  m_size += kLanczosBlock;
}

}  // namespace sc::spectral::detail
