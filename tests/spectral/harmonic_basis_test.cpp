#include "spectral/harmonic_basis.h"

#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <vector>

namespace sc::spectral {
namespace {

BasisResult basisOf(const testing::GeneratedMesh& mesh, int m) {
  BasisOptions options;
  options.m = m;
  return manifoldHarmonicBasis(laplaceOperators(mesh.V, mesh.F), options);
}

TEST(HarmonicBasis, UnitSphereSpectrumIsLTimesLPlusOneWithMultiplicities) {
  // Spherical harmonics: λ = l(l+1) with multiplicity 2l+1, i.e. 0 | 2,2,2 | 6×5 | 12×7.
  const BasisResult r = basisOf(testing::icosphere(4), 16);
  ASSERT_TRUE(r.ok()) << r.message;
  const Eigen::VectorXd& lambda = r.basis.eigenvalues;
  EXPECT_NEAR(lambda(0), 0.0, 1e-8);
  int k = 1;
  for (int l = 1; l <= 3; ++l) {
    const double exact = l * (l + 1);
    for (int j = 0; j < 2 * l + 1; ++j, ++k) {
      SCOPED_TRACE("l = " + std::to_string(l) + ", k = " + std::to_string(k));
      EXPECT_NEAR(lambda(k), exact, 0.02 * exact);
    }
  }
}

TEST(HarmonicBasis, AscendingAndMOrthonormal) {
  const auto mesh = testing::torus(60, 24);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions options;
  options.m = 60;
  const BasisResult r = manifoldHarmonicBasis(ops, options);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.basis.size(), 60);
  for (int k = 1; k < 60; ++k) EXPECT_LE(r.basis.eigenvalues(k - 1), r.basis.eigenvalues(k));
  EXPECT_LE(orthonormalityError(r.basis.vectors, ops.mass), 1e-8);
  EXPECT_LT(r.basis.shift, 0.0);
  // H also diagonalises S: HᵀSH = Λ.
  const Eigen::MatrixXd HtSH = r.basis.vectors.transpose() * (ops.stiffness * r.basis.vectors);
  EXPECT_LT((HtSH - Eigen::MatrixXd(r.basis.eigenvalues.asDiagonal())).cwiseAbs().maxCoeff(),
            1e-7 * r.basis.eigenvalues.maxCoeff());
}

TEST(HarmonicBasis, TwoDisjointSpheresGiveTwoZeroEigenvalues) {
  const BasisResult r = basisOf(testing::twoSpheres(3), 10);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_NEAR(r.basis.eigenvalues(0), 0.0, 1e-8);
  EXPECT_NEAR(r.basis.eigenvalues(1), 0.0, 1e-8);
  EXPECT_GT(r.basis.eigenvalues(2), 1.0) << "the third eigenvalue is the first non-constant harmonic (≈2)";
}

TEST(HarmonicBasis, EveryEigenvectorOfTwoEqualSpheresLivesOnOneSphere) {
  // Equal spheres make every eigenvalue at least double, and the solver mixes the spheres inside those eigenspaces;
  // the basis must come out localised (else dragging one sphere would move the other).
  const auto mesh = testing::twoSpheres(2);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions options;
  options.m = 20;
  const BasisResult r = manifoldHarmonicBasis(ops, options);
  ASSERT_TRUE(r.ok()) << r.message;
  const Eigen::Index half = mesh.V.rows() / 2;
  for (Eigen::Index k = 0; k < r.basis.size(); ++k) {
    const Eigen::VectorXd h = r.basis.vectors.col(k);
    const double onFirst = h.head(half).dot(ops.mass.head(half).cwiseProduct(h.head(half)));
    EXPECT_TRUE(onFirst < 1e-12 || onFirst > 1.0 - 1e-12) << "column " << k << " has " << onFirst << " on sphere A";
  }
  EXPECT_LE(orthonormalityError(r.basis.vectors, ops.mass), 1e-8);
}

TEST(HarmonicBasis, SignsAreDeterministic) {
  const auto mesh = testing::torus(30, 12);
  const BasisResult a = basisOf(mesh, 20);
  const BasisResult b = basisOf(mesh, 20);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a.basis.vectors, b.basis.vectors) << "the same input must give bit-identical vectors";
  for (Eigen::Index k = 0; k < a.basis.size(); ++k) {
    Eigen::Index i = 0;
    a.basis.vectors.col(k).cwiseAbs().maxCoeff(&i);
    EXPECT_GT(a.basis.vectors(i, k), 0.0) << "column " << k << ": largest entry must be positive";
  }
}

TEST(HarmonicBasis, ProgressIsReportedAndCancellationStopsTheSolve) {
  const auto mesh = testing::icosphere(3);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  std::vector<double> reported;
  BasisOptions options;
  options.m = 30;
  options.progress = [&reported](double fraction) {
    reported.push_back(fraction);
    return true;
  };
  ASSERT_TRUE(manifoldHarmonicBasis(ops, options).ok());
  ASSERT_GT(reported.size(), 2u);
  for (std::size_t i = 1; i < reported.size(); ++i) EXPECT_GE(reported[i], reported[i - 1]);
  EXPECT_EQ(reported.back(), 1.0);

  int calls = 0;
  options.progress = [&calls](double) { return ++calls < 5; };
  const BasisResult cancelled = manifoldHarmonicBasis(ops, options);
  EXPECT_EQ(cancelled.status, BasisStatus::Cancelled);
  EXPECT_EQ(calls, 5) << "the solve must stop at the first refusal";
  EXPECT_EQ(cancelled.basis.vectors.size(), 0);
}

TEST(HarmonicBasis, InvalidInputIsReportedNotCrashed) {
  const auto mesh = testing::icosphere(1);  // 42 vertices
  LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions options;
  options.m = 42;
  EXPECT_EQ(manifoldHarmonicBasis(ops, options).status, BasisStatus::InvalidInput) << "m must be < #V";
  options.m = 0;
  EXPECT_EQ(manifoldHarmonicBasis(ops, options).status, BasisStatus::InvalidInput);
  options.m = 10;
  ops.mass(3) = 0.0;
  const BasisResult r = manifoldHarmonicBasis(ops, options);
  EXPECT_EQ(r.status, BasisStatus::InvalidInput);
  EXPECT_FALSE(r.message.empty());
}

TEST(HarmonicBasis, IndefiniteStiffnessIsAFactorisationFailure) {
  const auto mesh = testing::icosphere(2);
  LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  ops.stiffness = -ops.stiffness;  // negative semi-definite: S − σM is no longer positive definite
  BasisOptions options;
  options.m = 10;
  EXPECT_EQ(manifoldHarmonicBasis(ops, options).status, BasisStatus::FactorizationFailed);
}

/// ‖S h − λ M h‖_{M⁻¹}/(|λ| + |σ|) of every column, the largest: the definition, column by column.
double largestResidualByDefinition(const LaplaceOperators& ops, const HarmonicBasis& basis) {
  double worst = 0.0;
  for (Eigen::Index k = 0; k < basis.size(); ++k) {
    const Eigen::VectorXd h = basis.vectors.col(k);
    const Eigen::VectorXd residual = ops.stiffness * h - basis.eigenvalues[k] * ops.mass.cwiseProduct(h);
    const double norm = std::sqrt(residual.cwiseAbs2().cwiseQuotient(ops.mass).sum());
    worst = std::max(worst, norm / (std::abs(basis.eigenvalues[k]) + std::abs(basis.shift)));
  }
  return worst;
}

TEST(HarmonicBasis, MaxRelativeResidualIsTheLargestOverEveryColumnIncludingAPartChunk) {
  const auto mesh = testing::torus(30, 12);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions options;
  options.m = 13;  // one chunk of 8 columns and one of 5
  BasisResult r = manifoldHarmonicBasis(ops, options);
  ASSERT_TRUE(r.ok()) << r.message;
  const double converged = largestResidualByDefinition(ops, r.basis);
  EXPECT_NEAR(r.maxResidual, converged, 1e-6 * converged);
  EXPECT_LE(r.maxResidual, 1e-8);
  // a wrong eigenvalue in the last, partial chunk is the largest residual, and it is found
  r.basis.eigenvalues[12] *= 1.01;
  const double wrong = largestResidualByDefinition(ops, r.basis);
  EXPECT_GT(wrong, 1e-4);
  EXPECT_NEAR(maxRelativeResidual(ops, r.basis), wrong, 1e-9 * wrong);
}

TEST(HarmonicBasis, OrthonormalityErrorOverBandsOfRowsIsTheWholeGramsDefect) {
  // more rows than one band (4096) and a last band that is not full
  const Eigen::Index n = 3 * 4096 + 17;
  const Eigen::MatrixXd h = Eigen::MatrixXd::Random(n, 7);
  const Eigen::VectorXd mass = Eigen::VectorXd::Random(n).cwiseAbs() + Eigen::VectorXd::Constant(n, 0.1);
  const Eigen::MatrixXd gram = h.transpose() * mass.asDiagonal() * h;
  const double direct = (gram - Eigen::MatrixXd::Identity(7, 7)).cwiseAbs().maxCoeff();
  EXPECT_NEAR(orthonormalityError(h, mass), direct, 1e-12 * direct);

  // an M-orthonormal basis whose last column is scaled by 1 + ε: the defect is (1 + ε)² − 1
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(h);
  const Eigen::MatrixXd orthonormal = qr.householderQ() * Eigen::MatrixXd::Identity(n, 7);
  Eigen::MatrixXd q = mass.cwiseSqrt().cwiseInverse().asDiagonal() * orthonormal;
  EXPECT_LE(orthonormalityError(q, mass), 1e-12);
  q.col(6) *= 1.001;
  EXPECT_NEAR(orthonormalityError(q, mass), 1.001 * 1.001 - 1.0, 1e-10);
}

}  // namespace
}  // namespace sc::spectral
