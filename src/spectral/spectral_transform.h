#pragma once
// Transforms between per-vertex signals and spectral coefficients in a manifold harmonic basis.

#include <Eigen/Core>

#include <vector>

namespace sc::spectral {

/// Forward transform Y = HᵀMX: the M-orthogonal projection coefficients of a per-vertex signal.
/// @param[in] H  #V by m, M-orthonormal basis.
/// @param[in] mass  #V lumped mass (diagonal of M).
/// @param[in] X  #V by d signal (d = 3 for positions or displacements).
/// @return m by d coefficients.
/// Cost: O(#V·m·d).
Eigen::MatrixXd spectralCoefficients(const Eigen::MatrixXd& H, const Eigen::VectorXd& mass, const Eigen::MatrixXd& X);

/// Inverse transform in displacement form X = X̂ + HZ.
/// @param[in] rest  #V by d rest signal X̂ (use a zero matrix for the plain synthesis HZ).
/// @param[in] H  #V by m basis.
/// @param[in] Z  m by d coefficients.
/// @return #V by d signal.
/// Cost: O(#V·m·d).
Eigen::MatrixXd reconstruct(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& H, const Eigen::MatrixXd& Z);

/// Inverse transform from a subset of coefficient rows: X = X̂ + Σ_{k ∈ rows} h_k z_k; rows not listed count as 0
/// (how a receiver reconstructs from the bands that arrived).
/// @param[in] rows  distinct row indices into Z, each in [0, m).
/// Cost: O(#V·|rows|·d).
Eigen::MatrixXd reconstructFromRows(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& H, const Eigen::MatrixXd& Z,
                                    const std::vector<int>& rows);

}  // namespace sc::spectral
