// Tests for tools/large_mesh/midpoint_subdivision.cpp (the million-vertex test mesh's subdivision).

#include "tools/large_mesh/midpoint_subdivision.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <set>
#include <utility>

namespace {

double area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    sum += 0.5 * (b - a).cross(c - a).norm();
  }
  return sum;
}

std::size_t edgeCount(const Eigen::MatrixXi& F) {
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int e = 0; e < 3; ++e) edges.emplace(std::minmax(F(f, e), F(f, (e + 1) % 3)));
  return edges.size();
}

}  // namespace

TEST(MidpointSubdivision, OneVertexPerEdgeFourTrianglesPerTriangleSameSurface) {
  const auto torus = sc::testing::torus(12, 8);
  const sc::tools::SubdividedMesh finer = sc::tools::subdivideMidpoints(torus.V, torus.F);
  const auto edges = static_cast<Eigen::Index>(edgeCount(torus.F));
  ASSERT_EQ(finer.V.rows(), torus.V.rows() + edges);
  ASSERT_EQ(finer.F.rows(), 4 * torus.F.rows());
  // The input vertices keep their indices and positions; the surface is the same (planar 1-to-4 splits).
  EXPECT_EQ(finer.V.topRows(torus.V.rows()), torus.V);
  EXPECT_NEAR(area(finer.V, finer.F), area(torus.V, torus.F), 1e-12 * area(torus.V, torus.F));
  // A closed manifold stays closed and manifold: every edge in exactly two triangles (Euler: V − E + F unchanged).
  const auto finerEdges = static_cast<Eigen::Index>(edgeCount(finer.F));
  EXPECT_EQ(finer.V.rows() - finerEdges + finer.F.rows(), torus.V.rows() - edges + torus.F.rows());
  EXPECT_EQ(2 * finerEdges, 3 * finer.F.rows());
  // Each new vertex is the midpoint of an input edge of its first face.
  const Eigen::Vector3d mid = 0.5 * (torus.V.row(torus.F(0, 0)) + torus.V.row(torus.F(0, 1))).transpose();
  EXPECT_TRUE(finer.V.row(finer.F(0, 1)).transpose().isApprox(mid));
}

TEST(MidpointSubdivision, ANonManifoldEdgeGetsOneMidpoint) {
  // Three triangles on one edge (0, 1): a fin.
  Eigen::MatrixXd V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  Eigen::MatrixXi F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const sc::tools::SubdividedMesh finer = sc::tools::subdivideMidpoints(V, F);
  EXPECT_EQ(finer.V.rows(), 5 + 7);  // edges: (0,1) once, plus two per triangle
  EXPECT_EQ(finer.F.rows(), 12);
}
