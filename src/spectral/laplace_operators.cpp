#include "spectral/laplace_operators.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

namespace sc::spectral {
namespace {

/// Edge lengths of a face, l[k] = length of the edge opposite corner k.
using FaceLengths = std::array<double, 3>;

FaceLengths faceLengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f) {
  FaceLengths l{};
  for (int k = 0; k < 3; ++k)
    l[static_cast<std::size_t>(k)] = (V.row(F(f, (k + 1) % 3)) - V.row(F(f, (k + 2) % 3))).norm();
  return l;
}

/// Smallest ε ≥ 0 such that every face satisfies l_i + l_j ≥ l_k + δ after adding ε to all lengths.
double mollificationEpsilon(const std::vector<FaceLengths>& lengths, double delta) {
  double epsilon = 0.0;
  for (const auto& l : lengths)
    for (std::size_t k = 0; k < 3; ++k) epsilon = std::max(epsilon, delta - l[(k + 1) % 3] - l[(k + 2) % 3] + l[k]);
  return epsilon;
}

/// Triangle area from its side lengths (Kahan's numerically stable Heron formula).
double heronArea(FaceLengths l) {
  std::sort(l.begin(), l.end(), std::greater<>());
  const double a = l[0], b = l[1], c = l[2];
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return 0.25 * std::sqrt(std::max(p, 0.0));
}

}  // namespace

LaplaceOperators laplaceOperators(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const LaplaceOptions& options) {
  assert(V.cols() == 3 && F.cols() == 3 && "V and F must have three columns");
  const Eigen::Index n = V.rows();

  // === step 1: edge lengths and the mollification that keeps every triangle non-degenerate
  std::vector<FaceLengths> lengths(static_cast<std::size_t>(F.rows()));
  double lengthSum = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    lengths[static_cast<std::size_t>(f)] = faceLengths(V, F, f);
    for (double l : lengths[static_cast<std::size_t>(f)]) lengthSum += l;
  }
  const double meanEdge = F.rows() > 0 ? lengthSum / (3.0 * static_cast<double>(F.rows())) : 0.0;
  LaplaceOperators ops;
  ops.mollifyEpsilon = mollificationEpsilon(lengths, options.mollifyMargin * meanEdge);
  for (auto& l : lengths)
    for (double& x : l) x += ops.mollifyEpsilon;

  // === step 2: per-face cotangent weights and lumped areas
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(F.rows()) * 12);
  ops.mass.setZero(n);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const FaceLengths& l = lengths[static_cast<std::size_t>(f)];
    const double area = heronArea(l);
    for (int k = 0; k < 3; ++k) {
      const auto sk = static_cast<std::size_t>(k);
      const double a = l[sk], b = l[(sk + 1) % 3], c = l[(sk + 2) % 3];
      const double w = area > 0.0 ? 0.5 * (b * b + c * c - a * a) / (4.0 * area) : 0.0;
      const int i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      triplets.emplace_back(i, j, -w);
      triplets.emplace_back(j, i, -w);
      triplets.emplace_back(i, i, w);
      triplets.emplace_back(j, j, w);
      ops.mass(F(f, k)) += area / 3.0;
    }
    ops.totalArea += area;
  }

  // === step 3: assemble (duplicates are summed)
  ops.stiffness.resize(n, n);
  ops.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  ops.stiffness.makeCompressed();
  return ops;
}

}  // namespace sc::spectral
