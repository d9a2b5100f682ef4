// Tests for src/model/mesh_proxy.cpp.

#include "model/mesh_proxy.h"

#include "spectral/surface_distance.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

namespace sc::model {
namespace {

TEST(MeshProxy, IndexesTheInputVerticesAndKeepsTheShape) {
  const auto torus = testing::torus(120, 50);  // 12,000 triangles
  const Eigen::MatrixXi proxy = proxyTriangles(torus.V, torus.F, 3000);
  EXPECT_NEAR(static_cast<double>(proxy.rows()), 3000.0, 60.0);
  ASSERT_GE(proxy.minCoeff(), 0);
  ASSERT_LT(proxy.maxCoeff(), torus.V.rows());
  const double diagonal = spectral::boundingBoxDiagonal(torus.V);
  EXPECT_LT(spectral::symmetricSurfaceDistance(torus.V, proxy, torus.V, torus.F, diagonal).maxRelative, 0.01);
  // The proxy follows a deformation of the input's vertices: moved vertices, moved proxy.
  const Eigen::MatrixXd moved = torus.V * 2.0;
  EXPECT_LT(spectral::symmetricSurfaceDistance(moved, proxy, moved, torus.F, 2.0 * diagonal).maxRelative, 0.01);
  EXPECT_EQ(proxyTriangles(torus.V, torus.F, 20000), torus.F) << "a mesh already small enough is its own proxy";
}

}  // namespace
}  // namespace sc::model
