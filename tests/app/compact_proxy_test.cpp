// Tests for src/app/gui/compact_proxy.cpp: the proxy's renumbering and its positions, normals, tints and
// reconstruction agree with the mesh's at the vertices it uses.

#include "app/gui/compact_proxy.h"

#include "app/gui/vertex_normals.h"
#include "model/mesh_proxy.h"
#include "spectral/reconstruction_kernel.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace {

using sc::app::CompactProxy;

TEST(CompactProxy, RenumbersTheUsedVerticesInOrderOfFirstUse) {
  Eigen::MatrixXi triangles(2, 3);
  triangles << 7, 2, 5,  //
      5, 2, 9;
  const CompactProxy proxy(triangles, 10);
  EXPECT_EQ(proxy.vertexCount(), 4);
  EXPECT_EQ(proxy.indices(), (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}));
  for (int v = 0; v < 10; ++v) EXPECT_EQ(proxy.uses(v), v == 2 || v == 5 || v == 7 || v == 9) << v;
  EXPECT_FALSE(proxy.uses(-1));
  EXPECT_FALSE(proxy.uses(10));
  EXPECT_TRUE(CompactProxy().empty());
  EXPECT_FALSE(CompactProxy().uses(0));
}

TEST(CompactProxy, GathersPositionsAndTintsAndShadesItsOwnTriangles) {
  const auto sphere = sc::testing::icosphere(3, 1.5, Eigen::Vector3d(0.5, 0, -1));
  const Eigen::MatrixXi triangles = sc::model::proxyTriangles(sphere.V, sphere.F, 200);
  CompactProxy proxy(triangles, static_cast<int>(sphere.V.rows()));
  ASSERT_LT(proxy.vertexCount(), sphere.V.rows());
  const std::vector<float> xyz = sc::spectral::interleavedPositions(sphere.V);
  std::vector<std::uint8_t> rgba(4 * static_cast<std::size_t>(sphere.V.rows()));
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<std::uint8_t>(i % 251);
  proxy.gatherPositions(xyz);
  proxy.updateNormals();
  proxy.gatherTints(rgba);

  // Proxy vertex j is mesh vertex triangles(t, c) wherever indices()[3t + c] == j.
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      const auto v = static_cast<std::size_t>(triangles(t, c));
      const std::size_t j = proxy.indices()[static_cast<std::size_t>(3 * t + c)];
      for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(proxy.positions()[3 * j + k], xyz[3 * v + k]);
      for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(proxy.tints()[4 * j + k], rgba[4 * v + k]);
    }
  }
  // Normals over the coarse triangles still point away from the sphere's centre.
  for (int j = 0; j < proxy.vertexCount(); ++j) {
    const auto at = [&](const std::vector<float>& a, int k) { return a[static_cast<std::size_t>(3 * j + k)]; };
    const Eigen::Vector3f n(at(proxy.normals(), 0), at(proxy.normals(), 1), at(proxy.normals(), 2));
    const Eigen::Vector3f radial =
        Eigen::Vector3f(at(proxy.positions(), 0) - 0.5f, at(proxy.positions(), 1), at(proxy.positions(), 2) + 1.0f);
    EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
    EXPECT_GT(n.dot(radial.normalized()), 0.9f) << "proxy vertex " << j;
  }
}

TEST(CompactProxy, ReconstructsTheMeshPositionsOfItsVertices) {
  const auto sphere = sc::testing::icosphere(3);
  const Eigen::MatrixXi triangles = sc::model::proxyTriangles(sphere.V, sphere.F, 300);
  CompactProxy proxy(triangles, static_cast<int>(sphere.V.rows()));
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Eigen::MatrixXd values(sphere.V.rows(), 12);
  for (Eigen::Index i = 0; i < values.size(); ++i) values.data()[i] = 0.05 * u(rng);
  const sc::spectral::QuantizedBasis K = sc::spectral::quantizeBasis(values);
  Eigen::MatrixXf Z(12, 3);
  for (Eigen::Index i = 0; i < Z.size(); ++i) Z.data()[i] = u(rng);
  const std::vector<float> rest = sc::spectral::interleavedPositions(sphere.V);
  std::vector<float> full(rest.size());
  sc::spectral::reconstructInterleaved(K, rest, Z, full);

  EXPECT_FALSE(proxy.hasBasis());
  proxy.setBasis(K, rest);
  ASSERT_TRUE(proxy.hasBasis());
  proxy.reconstruct(Z);
  std::set<std::size_t> checked;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      const auto v = static_cast<std::size_t>(triangles(t, c));
      const std::size_t j = proxy.indices()[static_cast<std::size_t>(3 * t + c)];
      for (std::size_t k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(proxy.positions()[3 * j + k], full[3 * v + k]);
      checked.insert(j);
    }
  }
  EXPECT_EQ(checked.size(), static_cast<std::size_t>(proxy.vertexCount()));
  proxy.clearBasis();
  EXPECT_FALSE(proxy.hasBasis());
}

}  // namespace
