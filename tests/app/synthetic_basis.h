#pragma once
// A synthetic basis and coefficients for viewport tests that show a display level without computing a real basis.

#include "spectral/quantized_basis.h"

#include <Eigen/Core>

#include <cmath>
#include <random>

namespace sc::testing {

/// A smooth-ish random basis: K_ik = scale·sin((k + 1)·x_i + phase_k) along axis k mod 3, deterministic; quantised as a
/// level holds it. Cost: O(#V·m).
inline spectral::QuantizedBasis syntheticBasis(const Eigen::MatrixXd& V, int m, float scale) {
  Eigen::MatrixXd K(V.rows(), m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> phase(0.0f, 6.28f);
  for (int k = 0; k < m; ++k) {
    const float p = phase(rng);
    const auto axis = static_cast<Eigen::Index>(k % 3);
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      K(i, k) = scale * std::sin(static_cast<float>(k + 1) * static_cast<float>(V(i, axis)) + p);
    }
  }
  return spectral::quantizeBasis(K);
}

/// m by 3 coefficients uniform in [−scale, scale], from `seed`.
inline Eigen::MatrixXf randomCoefficients(int m, float scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-scale, scale);
  Eigen::MatrixXf Z(m, 3);
  for (Eigen::Index i = 0; i < Z.size(); ++i) {
    Z.data()[i] = u(rng);
  }
  return Z;
}

}  // namespace sc::testing
