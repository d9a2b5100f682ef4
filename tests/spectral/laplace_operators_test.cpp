#include "spectral/laplace_operators.h"

#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace sc::spectral {
namespace {

struct NamedMesh {
  std::string name;
  testing::GeneratedMesh mesh;
};

/// A fan around vertex 0 with an obtuse triangle and a sliver whose apex is 1e-12 off the base line.
///
///        3
///       / |            4 is (0.5, 1e-12): the sliver 1-2-4 has area ~5e-13
///      /  |
///     0---1-4-2        (vertex 4 lies almost on the segment 1-2)
testing::GeneratedMesh obtuseAndSliver() {
  testing::GeneratedMesh m;
  m.V.resize(5, 3);
  m.V << -1, 0, 0,   //
      0, 0, 0,       //
      1, 0, 0,       //
      -0.2, 0.1, 0,  // flat obtuse apex over 0-1
      0.5, 1e-12, 0;
  m.F.resize(3, 3);
  m.F << 0, 1, 3,  //
      1, 4, 3,     //
      1, 2, 4;
  return m;
}

std::vector<NamedMesh> allMeshes() {
  return {{"icosphere", testing::icosphere(3)},
          {"torus", testing::torus(40, 16)},
          {"grid", testing::grid(12, 9)},
          {"twoSpheres", testing::twoSpheres(2)},
          {"obtuseAndSliver", obtuseAndSliver()}};
}

TEST(LaplaceOperators, InvariantsOnEveryTestMesh) {
  for (const auto& [name, mesh] : allMeshes()) {
    SCOPED_TRACE(name);
    const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
    const Eigen::MatrixXd S = Eigen::MatrixXd(ops.stiffness);
    ASSERT_TRUE(S.allFinite());
    ASSERT_TRUE(ops.mass.allFinite());
    EXPECT_LT((S * Eigen::VectorXd::Ones(S.rows())).cwiseAbs().maxCoeff(), 1e-10 * S.cwiseAbs().maxCoeff())
        << "constants must be in the kernel";
    EXPECT_LT((S - S.transpose()).cwiseAbs().maxCoeff(), 1e-14 * S.cwiseAbs().maxCoeff()) << "S must be symmetric";
    EXPECT_GT(ops.mass.minCoeff(), 0.0) << "every vertex needs positive mass";
    EXPECT_NEAR(ops.mass.sum(), ops.totalArea, 1e-12 * ops.totalArea);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
    EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-9 * eig.eigenvalues().maxCoeff()) << "S must be PSD";
  }
}

TEST(LaplaceOperators, SphereAreaAndNoMollificationOnGoodMeshes) {
  const auto sphere = testing::icosphere(4);
  const LaplaceOperators ops = laplaceOperators(sphere.V, sphere.F);
  EXPECT_NEAR(ops.totalArea, 4.0 * std::numbers::pi, 0.01 * 4.0 * std::numbers::pi);
  EXPECT_EQ(ops.mollifyEpsilon, 0.0) << "a well-shaped mesh must not be altered";
}

TEST(LaplaceOperators, SliverIsMollifiedToFiniteWeights) {
  const auto mesh = obtuseAndSliver();
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  EXPECT_GT(ops.mollifyEpsilon, 0.0) << "the sliver violates the margin, so lengths must be mollified";
  EXPECT_TRUE(Eigen::MatrixXd(ops.stiffness).allFinite());
}

TEST(LaplaceOperators, GridMatchesTheFivePointStencilInside) {
  // On a uniform right-triangle grid the cotangent Laplacian is the 5-point stencil: 4 on the diagonal, -1 to
  // the axis neighbours, 0 across the diagonals.
  const auto mesh = testing::grid(4, 4);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const int centre = 2 * 5 + 2;
  EXPECT_NEAR(ops.stiffness.coeff(centre, centre), 4.0, 1e-12);
  EXPECT_NEAR(ops.stiffness.coeff(centre, centre + 1), -1.0, 1e-12);
  EXPECT_NEAR(ops.stiffness.coeff(centre, centre + 5), -1.0, 1e-12);
  EXPECT_NEAR(ops.stiffness.coeff(centre, centre + 6), 0.0, 1e-12);
}

/// The same S from each face's twelve triplets (cotangents from dot and cross products), assembled by Eigen's
/// setFromTriplets(): the reference the direct assembly must equal, pattern and values.
SparseMatrix tripletStiffness(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int corner = F(f, k), i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      const Eigen::Vector3d a = V.row(i) - V.row(corner), b = V.row(j) - V.row(corner);
      const double w = 0.5 * a.dot(b) / a.cross(b).norm();
      triplets.insert(triplets.end(), {{i, j, -w}, {j, i, -w}, {i, i, w}, {j, j, w}});
    }
  SparseMatrix S(V.rows(), V.rows());
  S.setFromTriplets(triplets.begin(), triplets.end());
  return S;
}

TEST(LaplaceOperators, EqualsTheFacesTripletsSummedWithAFinAndAnUnusedVertex) {
  testing::GeneratedMesh mesh = testing::torus(24, 10);
  // A fin: a third face on the edge of face 0 (a non-manifold edge), and a last vertex no face uses.
  const Eigen::Index n = mesh.V.rows();
  mesh.V.conservativeResize(n + 2, 3);
  mesh.V.row(n) = (mesh.V.row(mesh.F(0, 0)) + mesh.V.row(mesh.F(0, 1))) / 2 + Eigen::RowVector3d(0, 0, 0.5);
  mesh.V.row(n + 1) = Eigen::RowVector3d(9, 9, 9);
  mesh.F.conservativeResize(mesh.F.rows() + 1, 3);
  mesh.F.row(mesh.F.rows() - 1) << mesh.F(0, 1), mesh.F(0, 0), static_cast<int>(n);

  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  ASSERT_EQ(ops.mollifyEpsilon, 0.0);
  const SparseMatrix reference = tripletStiffness(mesh.V, mesh.F);
  ASSERT_EQ(ops.stiffness.nonZeros(), reference.nonZeros());
  ASSERT_TRUE(ops.stiffness.isCompressed());
  for (Eigen::Index c = 0; c < reference.outerSize(); ++c) {
    ASSERT_EQ(ops.stiffness.outerIndexPtr()[c + 1], reference.outerIndexPtr()[c + 1]) << "column " << c;
    SparseMatrix::InnerIterator entry(ops.stiffness, c);
    for (SparseMatrix::InnerIterator expected(reference, c); expected; ++expected, ++entry) {
      ASSERT_EQ(entry.row(), expected.row()) << "column " << c << ": rows sorted, each once";
      EXPECT_NEAR(entry.value(), expected.value(), 1e-12 * (1.0 + std::abs(expected.value())));
    }
  }
  EXPECT_EQ(ops.stiffness.col(n + 1).nonZeros(), 0) << "a vertex no face uses has an empty column";
  EXPECT_EQ(ops.mass(n + 1), 0.0);
}

TEST(LaplaceOperators, MovesHandOverTheArraysWithoutCopyingThem) {
  // Eigen 3.4's SparseMatrix has no move: a defaulted move of the operators would copy S (36 MB at 437k vertices).
  LaplaceOperators ops = laplaceOperators(testing::icosphere(2).V, testing::icosphere(2).F);
  const SparseMatrix expected = ops.stiffness;
  const double* values = ops.stiffness.valuePtr();
  const double* areas = ops.mass.data();
  LaplaceOperators moved(std::move(ops));
  EXPECT_EQ(moved.stiffness.valuePtr(), values);
  EXPECT_EQ(moved.mass.data(), areas);
  LaplaceOperators assigned = laplaceOperators(testing::icosphere(1).V, testing::icosphere(1).F);
  assigned = std::move(moved);
  EXPECT_EQ(assigned.stiffness.valuePtr(), values);
  EXPECT_EQ(assigned.mass.data(), areas);
  EXPECT_EQ(assigned.stiffness.nonZeros(), expected.nonZeros());
  EXPECT_EQ((assigned.stiffness - expected).norm(), 0.0);
  EXPECT_EQ(moved.stiffness.nonZeros(), 0) << "the assignment's old arrays went with a temporary, not into `moved`";
}

}  // namespace
}  // namespace sc::spectral
