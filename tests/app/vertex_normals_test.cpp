// Tests for src/app/gui/vertex_normals.cpp.

#include "app/gui/vertex_normals.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

using sc::app::vertexNormals;

TEST(VertexNormals, UnitAndOutwardOnIcosphere) {
  for (int subdivisions : {1, 3}) {
    const auto mesh = sc::testing::icosphere(subdivisions, 2.0, Eigen::Vector3d(1, -2, 3));
    const Eigen::MatrixXd N = vertexNormals(mesh.V, mesh.F);
    ASSERT_EQ(N.rows(), mesh.V.rows());
    ASSERT_EQ(N.cols(), 3);
    for (Eigen::Index i = 0; i < N.rows(); ++i) {
      const Eigen::RowVector3d radial = (mesh.V.row(i) - Eigen::RowVector3d(1, -2, 3)).normalized();
      EXPECT_NEAR(N.row(i).norm(), 1.0, 1e-12) << "vertex " << i;
      EXPECT_GT(N.row(i).dot(radial), 0.99) << "vertex " << i << " should point away from the centre";
    }
  }
}

TEST(VertexNormals, OutwardFromTubeOnTorus) {
  const auto mesh = sc::testing::torus(48, 24, 1.0, 0.3);
  const Eigen::MatrixXd N = vertexNormals(mesh.V, mesh.F);
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const Eigen::RowVector3d p = mesh.V.row(i);
    const Eigen::RowVector3d tubeCentre = Eigen::RowVector3d(p.x(), p.y(), 0.0).normalized();
    EXPECT_NEAR(N.row(i).norm(), 1.0, 1e-12);
    EXPECT_GT(N.row(i).dot((p - tubeCentre).normalized()), 0.98) << "vertex " << i;
  }
}

TEST(VertexNormals, FlippedFacesGiveInwardNormals) {
  auto mesh = sc::testing::icosphere(2);
  mesh.F.col(1).swap(mesh.F.col(2));
  const Eigen::MatrixXd N = vertexNormals(mesh.V, mesh.F);
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    EXPECT_LT(N.row(i).dot(mesh.V.row(i).normalized()), -0.99);
  }
}

// Vertex 0 is shared by a big triangle in z = 0 (doubled area 4, normal +z) and a small one in x = 0 (doubled
// area 1, normal +x):
//
//      y                        z
//      2 +                      1 + 4
//        | .                      | .
//        |   .  big (0 1 2)       |   .  small (0 3 4)
//        |     .                  |     .
//      0 +-------+ 1  x         0 +-------+ 3  y
//                2                        1
//
// Area weighting gives n0 = normalise((1, 0, 4)); vertex 5 is referenced by no face and gets zero.
TEST(VertexNormals, AreaWeightedAndZeroForUnreferenced) {
  Eigen::MatrixXd V(6, 3);
  V << 0, 0, 0,  //
      2, 0, 0,   //
      0, 2, 0,   //
      0, 1, 0,   //
      0, 0, 1,   //
      5, 5, 5;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2,  //
      0, 3, 4;
  const Eigen::MatrixXd N = vertexNormals(V, F);
  const Eigen::RowVector3d expected = Eigen::RowVector3d(1, 0, 4).normalized();
  EXPECT_LT((N.row(0) - expected).norm(), 1e-12) << "the larger face must dominate";
  EXPECT_LT((N.row(1) - Eigen::RowVector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((N.row(4) - Eigen::RowVector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_EQ(N.row(5).norm(), 0.0) << "an unreferenced vertex has no normal";
}

TEST(VertexNormals, EmptyMesh) {
  const Eigen::MatrixXd N = vertexNormals(Eigen::MatrixXd(0, 3), Eigen::MatrixXi(0, 3));
  EXPECT_EQ(N.rows(), 0);
}
