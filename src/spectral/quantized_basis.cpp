#include "spectral/quantized_basis.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sc::spectral {

namespace {
constexpr double kMaxLevel = kQuantizedBasisLevels;
}  // namespace

QuantizedBasis quantizeBasis(const Eigen::MatrixXd& K) {
  assert(K.allFinite() && "K must be finite");
  QuantizedBasis out;
  out.Q.resize(K.rows(), K.cols());
  out.scale.resize(K.cols());
  for (Eigen::Index j = 0; j < K.cols(); ++j) {
    const double top = K.rows() > 0 ? K.col(j).cwiseAbs().maxCoeff() : 0.0;
    const double scale = top / kMaxLevel;
    out.scale(j) = static_cast<float>(scale);
    // Divide by the float scale the kernel multiplies with, so that rounding is to the nearest representable value.
    const double step = static_cast<double>(out.scale(j));
    for (Eigen::Index i = 0; i < K.rows(); ++i) {
      const double q = step > 0.0 ? std::round(K(i, j) / step) : 0.0;
      out.Q(i, j) = static_cast<std::int16_t>(std::clamp(q, -kMaxLevel, kMaxLevel));
    }
  }
  return out;
}

Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> dequantized(const QuantizedBasis& K) {
  return K.Q.cast<float>() * K.scale.asDiagonal();
}

double quantizationBound(const QuantizedBasis& K, const Eigen::MatrixXf& Z) {
  assert(Z.rows() == K.cols() && Z.cols() == 3 && "Z must be m by 3");
  return (0.5 * K.scale.cast<double>() * Z.cast<double>().cwiseAbs()).maxCoeff();
}

}  // namespace sc::spectral
