#pragma once
// QuantizedBasis: a level's reduced basis K (n' by m) stored as 16-bit integers with one float scale per column,
// K(i, j) ≈ scale(j)·Q(i, j) with scale(j) = max_i |K(i, j)| / L and Q(i, j) = round(K(i, j) / scale(j)) in
// [−L, L], L = kQuantizedBasisLevels = 4095: 13 significant bits stored in int16. Half the bytes of float32 K, in
// memory, on the wire and in the GPU's texture; the per-frame kernel folds the scales into Z once
// (Z'(j, c) = scale(j)·Z(j, c)) and reads only Q (reconstruction_kernel.h).
//
// Why 13 bits and not 16: the level payload's K compresses to what its low bits cost (near-random residuals), and
// the bound is 1e-4 of the diagonal. Measured over the loss experiment's drag at every level of the real
// meshes (tests/spectral/quantized_basis_test.cpp): 16 bits gave at most 3.7e-6 of the diagonal, 13 bits stay
// within the bound with room (the test's figure), and the 100k dragon's full level shrinks from 13.9 MB to about
// 10 MB compressed (docs/benchmarks.md).
//
// Error: |K − scale·Q| ≤ scale(j)/2 = max_i |K(i, j)| / (2L) per entry, so a reconstructed position is off by at
// most Σ_j |Z(j, c)|·scale(j)/2 per coordinate (bounded here by quantizationBound(); the real-mesh test in
// tests/spectral/quantized_basis_test.cpp measures it over a drag against float32 K).

#include <Eigen/Core>

#include <cstdint>

namespace sc::spectral {

/// n' by m int16, row-major: the kernel streams one row (m values) per output vertex.
using RowMatrixXs = Eigen::Matrix<std::int16_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The largest |Q(i, j)|: 2¹² − 1, 13 significant bits (sign included) in each int16 entry.
inline constexpr int kQuantizedBasisLevels = 4095;

struct QuantizedBasis {
  RowMatrixXs Q;             ///< n' by m quantised entries, each in [−kQuantizedBasisLevels, kQuantizedBasisLevels].
  Eigen::RowVectorXf scale;  ///< 1 by m, ≥ 0 and finite: K(i, j) ≈ scale(j)·Q(i, j).

  [[nodiscard]] Eigen::Index rows() const { return Q.rows(); }
  [[nodiscard]] Eigen::Index cols() const { return Q.cols(); }
  /// Entry (i, j) dequantised, scale(j)·Q(i, j).
  [[nodiscard]] float operator()(Eigen::Index i, Eigen::Index j) const {
    return scale(j) * static_cast<float>(Q(i, j));
  }
  /// Row i dequantised, 1 by m. Cost: O(m).
  [[nodiscard]] Eigen::RowVectorXf row(Eigen::Index i) const { return Q.row(i).cast<float>().cwiseProduct(scale); }
  /// Z'(j, c) = scale(j)·Z(j, c): the coefficients the kernel and the shader multiply Q with. Z: m by 3.
  [[nodiscard]] Eigen::MatrixXf scaled(const Eigen::MatrixXf& Z) const { return scale.transpose().asDiagonal() * Z; }
  /// Rows `rows` of this basis (e.g. a compact proxy's), same scales. Cost: O(#rows·m).
  template <class Indices>
  [[nodiscard]] QuantizedBasis gathered(const Indices& rows) const {
    QuantizedBasis out;
    out.scale = scale;
    out.Q.resize(static_cast<Eigen::Index>(rows.size()), cols());
    Eigen::Index r = 0;
    for (const auto i : rows) out.Q.row(r++) = Q.row(static_cast<Eigen::Index>(i));
    return out;
  }

  /// Same shape, entries and scales (bit for bit).
  friend bool operator==(const QuantizedBasis& a, const QuantizedBasis& b) {
    return a.Q.rows() == b.Q.rows() && a.Q.cols() == b.Q.cols() && a.scale.size() == b.scale.size() && a.Q == b.Q &&
           a.scale == b.scale;
  }
};

/// Quantises K column by column (scale = max|K(:, j)|/kQuantizedBasisLevels; an all-zero column gets scale 0 and
/// Q = 0).
/// @param[in] K  n' by m, finite. Cost: O(n'·m), two passes.
[[nodiscard]] QuantizedBasis quantizeBasis(const Eigen::MatrixXd& K);

/// scale·Q as float32, n' by m (tests and tools; the product never keeps it). Cost: O(n'·m), 4·n'·m bytes.
[[nodiscard]] Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> dequantized(
    const QuantizedBasis& K);

/// Upper bound of the quantisation's position error for coefficients Z (m by 3): max over coordinates c of
/// Σ_j scale(j)/2·|Z(j, c)|. Cost: O(m).
[[nodiscard]] double quantizationBound(const QuantizedBasis& K, const Eigen::MatrixXf& Z);

}  // namespace sc::spectral
