#include "spectral/hausdorff.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace sc::spectral {
namespace {

/// Brute-force O(n·n') one-sided Hausdorff distance, the reference for the kd-tree version.
double bruteForceOneSided(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < B.rows(); ++j) {
      const Eigen::RowVector3d d = A.row(i) - B.row(j);
      best = std::min(best, std::sqrt(d(0) * d(0) + d(1) * d(1) + d(2) * d(2)));
    }
    worst = std::max(worst, best);
  }
  return worst;
}

Eigen::MatrixXd randomPoints(Eigen::Index n, std::mt19937& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> uniform(-scale, scale);
  Eigen::MatrixXd P(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) P(i, k) = uniform(rng);
  return P;
}

void expectMatchesBruteForce(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const HausdorffDistance d = hausdorffDistance(A, B);
  EXPECT_EQ(d.aToB, bruteForceOneSided(A, B));
  EXPECT_EQ(d.bToA, bruteForceOneSided(B, A));
  EXPECT_EQ(d.value, std::max(d.aToB, d.bToA));
}

TEST(Hausdorff, MatchesBruteForceOnRandomSets) {
  std::mt19937 rng(7);
  for (const auto& [n, nPrime] : {std::pair{1, 1}, {5, 300}, {200, 37}, {500, 500}, {1000, 64}}) {
    SCOPED_TRACE(::testing::Message() << n << " vs " << nPrime);
    const Eigen::MatrixXd A = randomPoints(n, rng);
    const Eigen::MatrixXd B = randomPoints(nPrime, rng, 1.5);
    expectMatchesBruteForce(A, B);
  }
}

TEST(Hausdorff, MatchesBruteForceOnGeneratedMeshes) {
  const auto sphere = testing::icosphere(3);
  const auto coarse = testing::icosphere(2, 1.05, {0.02, 0.0, -0.01});
  const auto torus = testing::torus(40, 16);
  const auto grid = testing::grid(20, 20);
  expectMatchesBruteForce(sphere.V, coarse.V);
  expectMatchesBruteForce(torus.V, sphere.V);
  expectMatchesBruteForce(grid.V, torus.V);
  expectMatchesBruteForce(testing::twoSpheres(2).V, sphere.V);
}

TEST(Hausdorff, IsSymmetric) {
  std::mt19937 rng(11);
  const Eigen::MatrixXd A = randomPoints(300, rng);
  const Eigen::MatrixXd B = randomPoints(120, rng, 2.0);
  const HausdorffDistance ab = hausdorffDistance(A, B);
  const HausdorffDistance ba = hausdorffDistance(B, A);
  EXPECT_EQ(ab.value, ba.value);
  EXPECT_EQ(ab.aToB, ba.bToA);
  EXPECT_EQ(ab.bToA, ba.aToB);
  EXPECT_NE(ab.aToB, ab.bToA) << "a random pair of sets of different spread is not one-sided symmetric";
}

TEST(Hausdorff, IsZeroForIdenticalSetsAndForPermutations) {
  const auto torus = testing::torus(30, 12);
  EXPECT_EQ(hausdorffDistance(torus.V, torus.V).value, 0.0);
  const Eigen::MatrixXd reversed = torus.V.colwise().reverse();
  const HausdorffDistance d = hausdorffDistance(torus.V, reversed);
  EXPECT_EQ(d.value, 0.0) << "a point set does not depend on vertex order";
  EXPECT_GT(maxVertexError(torus.V, reversed), 0.0) << "…but the same-connectivity error does";
}

TEST(Hausdorff, EmptySets) {
  const Eigen::MatrixXd empty(0, 3);
  const Eigen::MatrixXd one = Eigen::MatrixXd::Zero(1, 3);
  EXPECT_EQ(hausdorffDistance(empty, empty).value, 0.0);
  EXPECT_TRUE(std::isinf(hausdorffDistance(one, empty).value));
  EXPECT_TRUE(std::isinf(hausdorffDistance(empty, one).value));
  EXPECT_EQ(maxVertexError(empty, empty), 0.0);
}

TEST(Hausdorff, TranslationByAVectorBoundsBothDistances) {
  const auto sphere = testing::icosphere(3);
  const Eigen::RowVector3d shift(0.3, -0.1, 0.2);
  const Eigen::MatrixXd moved = sphere.V.rowwise() + shift;
  EXPECT_NEAR(maxVertexError(sphere.V, moved), shift.norm(), 1e-15);
  EXPECT_LE(hausdorffDistance(sphere.V, moved).value, shift.norm() + 1e-15);
}

TEST(MaxVertexError, BoundsHausdorffForSameConnectivitySets) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (const auto& mesh : {testing::icosphere(3), testing::torus(40, 16), testing::grid(15, 15)}) {
    Eigen::MatrixXd deformed = mesh.V;
    for (Eigen::Index i = 0; i < deformed.size(); ++i) deformed(i) += noise(rng);
    const double bound = maxVertexError(mesh.V, deformed);
    const HausdorffDistance d = hausdorffDistance(mesh.V, deformed);
    EXPECT_GT(d.value, 0.0);
    EXPECT_LE(d.value, bound);
    EXPECT_LE(d.aToB, bound);
    EXPECT_LE(d.bToA, bound);
  }
}

TEST(NearestPointIndex, AnswersRepeatedQueriesAgainstOneReference) {
  const auto sphere = testing::icosphere(3);
  const NearestPointIndex index(sphere.V);
  EXPECT_EQ(index.nearestDistance(sphere.V.row(17).transpose()), 0.0);
  EXPECT_NEAR(index.nearestDistance(Eigen::Vector3d::Zero()), 1.0, 1e-12) << "every vertex is on the unit sphere";
  EXPECT_EQ(index.maxNearestDistance(sphere.V), 0.0);
  // the row of the nearest point: a vertex itself, and a point pushed out from vertex 17 along its normal
  EXPECT_EQ(index.nearestIndex(sphere.V.row(17).transpose()), 17);
  EXPECT_EQ(index.nearestIndex(1.05 * sphere.V.row(23).transpose()), 23);
  const Eigen::MatrixXd none(0, 3);
  EXPECT_EQ(NearestPointIndex(none).nearestIndex(Eigen::Vector3d::Zero()), -1);
}

TEST(BoundingBoxDiagonal, UnitCubeAndNormalisation) {
  const auto grid = testing::grid(4, 4);  // [0,1]² at z = 0
  EXPECT_DOUBLE_EQ(boundingBoxDiagonal(grid.V), std::sqrt(2.0));
  Eigen::MatrixXd cube(2, 3);
  cube << 0, 0, 0, 2, 3, 6;
  EXPECT_DOUBLE_EQ(boundingBoxDiagonal(cube), 7.0);
  EXPECT_DOUBLE_EQ(percentOfDiagonal(0.35, 7.0), 5.0);
  EXPECT_EQ(boundingBoxDiagonal(Eigen::MatrixXd(0, 3)), 0.0);
  EXPECT_TRUE(std::isnan(percentOfDiagonal(1.0, 0.0)));
}

}  // namespace
}  // namespace sc::spectral
