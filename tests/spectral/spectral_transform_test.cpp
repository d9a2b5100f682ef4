#include "spectral/spectral_transform.h"

#include "spectral/harmonic_basis.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

namespace sc::spectral {
namespace {

class SpectralTransform : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto mesh = testing::torus(40, 16);
    s_ops = laplaceOperators(mesh.V, mesh.F);
    s_rest = mesh.V;
    BasisOptions options;
    options.m = 40;
    s_basis = manifoldHarmonicBasis(s_ops, options).basis;
  }
  static inline LaplaceOperators s_ops;
  static inline HarmonicBasis s_basis;
  static inline Eigen::MatrixXd s_rest;
};

TEST_F(SpectralTransform, SignalInTheSpanIsReconstructedExactly) {
  ASSERT_EQ(s_basis.size(), 40);
  const Eigen::MatrixXd Z = Eigen::MatrixXd::Random(40, 3);
  const Eigen::MatrixXd X = reconstruct(s_rest, s_basis.vectors, Z);
  const Eigen::MatrixXd back = spectralCoefficients(s_basis.vectors, s_ops.mass, X - s_rest);
  EXPECT_LT((back - Z).cwiseAbs().maxCoeff(), 1e-9);
}

TEST_F(SpectralTransform, ParsevalLinksCoefficientAndShapeErrors) {
  // ‖H c‖_M = ‖c‖₂ for an M-orthonormal basis.
  const Eigen::VectorXd c = Eigen::VectorXd::Random(40);
  const Eigen::VectorXd x = s_basis.vectors * c;
  EXPECT_NEAR(std::sqrt(x.dot(s_ops.mass.cwiseProduct(x))), c.norm(), 1e-9 * c.norm());
}

TEST_F(SpectralTransform, ReconstructionFromRowsTreatsMissingRowsAsZero) {
  const Eigen::MatrixXd Z = Eigen::MatrixXd::Random(40, 3);
  std::vector<int> all(40);
  for (int k = 0; k < 40; ++k) all[static_cast<std::size_t>(k)] = k;
  EXPECT_LT((reconstructFromRows(s_rest, s_basis.vectors, Z, all) - reconstruct(s_rest, s_basis.vectors, Z))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);

  const std::vector<int> even = {0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30, 32, 34, 36, 38};
  Eigen::MatrixXd zeroed = Z;
  for (int k = 1; k < 40; k += 2) zeroed.row(k).setZero();
  EXPECT_LT((reconstructFromRows(s_rest, s_basis.vectors, Z, even) - reconstruct(s_rest, s_basis.vectors, zeroed))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  EXPECT_EQ(reconstructFromRows(s_rest, s_basis.vectors, Z, {}), s_rest) << "no rows: the rest shape";
}

TEST_F(SpectralTransform, LowPassOfTheRestShapeApproximatesIt) {
  // Absolute coefficients Y = HᵀMX̂ give the low-pass shape HY; on a smooth torus it is close to the rest shape.
  const Eigen::MatrixXd Y = spectralCoefficients(s_basis.vectors, s_ops.mass, s_rest);
  const Eigen::MatrixXd lowPass = reconstruct(Eigen::MatrixXd::Zero(s_rest.rows(), 3), s_basis.vectors, Y);
  const double diagonal = (s_rest.colwise().maxCoeff() - s_rest.colwise().minCoeff()).norm();
  EXPECT_LT((lowPass - s_rest).rowwise().norm().maxCoeff(), 0.05 * diagonal);
}

}  // namespace
}  // namespace sc::spectral
