#include "spectral/mesh_components.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

namespace sc::spectral {
namespace {

TEST(MeshComponents, TwoSpheresAreTwoComponents) {
  const auto mesh = testing::twoSpheres(1);
  Eigen::VectorXi labels;
  EXPECT_EQ(connectedComponents(mesh.V.rows(), mesh.F, labels), 2);
  EXPECT_EQ(labels(0), 0);
  EXPECT_EQ(labels(mesh.V.rows() - 1), 1);
}

TEST(MeshComponents, IsolatedVertexIsItsOwnComponent) {
  const auto mesh = testing::torus(8, 6);
  Eigen::VectorXi labels;
  EXPECT_EQ(connectedComponents(mesh.V.rows() + 1, mesh.F, labels), 2);
  EXPECT_EQ(labels(mesh.V.rows()), 1);
}

}  // namespace
}  // namespace sc::spectral
