#include "spectral/closest_point.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace sc::spectral {
namespace {

/// Closest point by testing every face.
struct BruteForceHit {
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d point;
};

BruteForceHit bruteForce(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& p) {
  BruteForceHit best;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d w = closestPointOnTriangle(p, a, b, c);
    const Eigen::Vector3d x = w(0) * a + w(1) * b + w(2) * c;
    if ((p - x).norm() < best.distance) best = {(p - x).norm(), x};
  }
  return best;
}

/// #Q random points in the bounding box of V grown by `margin` on each side.
Eigen::MatrixXd randomQueries(const Eigen::MatrixXd& V, int count, double margin, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const Eigen::RowVector3d lo = V.colwise().minCoeff().array() - margin, hi = V.colwise().maxCoeff().array() + margin;
  Eigen::MatrixXd Q(count, 3);
  for (int q = 0; q < count; ++q)
    for (int c = 0; c < 3; ++c) Q(q, c) = lo(c) + unit(rng) * (hi(c) - lo(c));
  return Q;
}

TEST(ClosestPointOnTriangle, EachRegion) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(closestPointOnTriangle({0.2, 0.3, 5}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0.2, 0.3)));  // face
  EXPECT_EQ(closestPointOnTriangle({-1, -1, 2}, a, b, c), Eigen::Vector3d(1, 0, 0));                     // vertex a
  EXPECT_EQ(closestPointOnTriangle({3, -1, 0}, a, b, c), Eigen::Vector3d(0, 1, 0));                      // vertex b
  EXPECT_EQ(closestPointOnTriangle({-1, 3, 0}, a, b, c), Eigen::Vector3d(0, 0, 1));                      // vertex c
  EXPECT_TRUE(closestPointOnTriangle({0.25, -2, 1}, a, b, c).isApprox(Eigen::Vector3d(0.75, 0.25, 0)));  // edge ab
  EXPECT_TRUE(closestPointOnTriangle({1, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(0, 0.5, 0.5)));        // edge bc
}

TEST(ClosestPointOnTriangle, NoCloserPointAmongDenseSamplesAndDegenerateSafe) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const auto random = [&] { return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)); };
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a = random(), b = random(), c = trial % 10 == 0 ? a + 1e-9 * random() : random();
    const Eigen::Vector3d p = 2 * random();
    const Eigen::Vector3d w = closestPointOnTriangle(p, a, b, c);
    ASSERT_GE(w.minCoeff(), 0.0);
    ASSERT_NEAR(w.sum(), 1.0, 1e-15);
    const double d = (p - (w(0) * a + w(1) * b + w(2) * c)).norm();
    constexpr int kSteps = 40;
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double u = double(i) / kSteps, v = double(j) / kSteps;
        ASSERT_LE(d, (p - ((1 - u - v) * a + u * b + v * c)).norm() + 1e-12);
      }
  }
}

TEST(ClosestPointQuery, MatchesBruteForceOnRandomQueries) {
  for (const auto& mesh : {testing::icosphere(3), testing::torus(40, 16), testing::grid(12, 9)}) {
    const Eigen::MatrixXd Q = randomQueries(mesh.V, 400, 0.5, 11);
    const ClosestPoints hits = closestPoints(mesh.V, mesh.F, Q);
    for (Eigen::Index q = 0; q < Q.rows(); ++q) {
      const BruteForceHit expected = bruteForce(mesh.V, mesh.F, Q.row(q).transpose());
      ASSERT_NEAR(hits.distances(q), expected.distance, 1e-12) << "query " << q;
      EXPECT_LT((hits.points.row(q).transpose() - expected.point).norm(), 1e-9) << "query " << q;
      EXPECT_NEAR((Q.row(q) - hits.points.row(q)).norm(), hits.distances(q), 1e-15);
    }
  }
}

TEST(ClosestPointQuery, BarycentricWeightsAreConvexAndGiveThePoint) {
  const auto mesh = testing::torus(30, 12);
  const Eigen::MatrixXd Q = randomQueries(mesh.V, 1000, 0.2, 3);
  const ClosestPoints hits = ClosestPointQuery(mesh.V, mesh.F).query(Q);
  ASSERT_GE(hits.barycentric.minCoeff(), 0.0);
  EXPECT_LT((hits.barycentric.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-15);
  for (Eigen::Index q = 0; q < Q.rows(); ++q) {
    Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 3; ++k) x += hits.barycentric(q, k) * mesh.V.row(mesh.F(hits.faces(q), k));
    EXPECT_LT((x - hits.points.row(q)).norm(), 1e-15);
  }
}

TEST(ClosestPointQuery, VerticesAreTheirOwnClosestPointsAndThreadsAgree) {
  const auto mesh = testing::icosphere(4);
  const ClosestPointQuery query(mesh.V, mesh.F);
  const ClosestPoints one = query.query(mesh.V, 1), three = query.query(mesh.V, 3);
  EXPECT_LT(one.distances.maxCoeff(), 1e-15);
  EXPECT_EQ(one.faces, three.faces);
  EXPECT_EQ(one.barycentric, three.barycentric);
  EXPECT_EQ(one.distances, three.distances);
}

}  // namespace
}  // namespace sc::spectral
