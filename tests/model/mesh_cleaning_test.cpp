// cleanMesh(): every count of MeshCleanReport on small hand-built soups, and the (V, F) it leaves behind.

#include "model/mesh_cleaning.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <array>
#include <initializer_list>
#include <vector>

namespace sc::model {
namespace {

Eigen::MatrixXd positions(std::initializer_list<std::array<double, 3>> rows) {
  Eigen::MatrixXd V(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::Index r = 0;
  for (const auto& p : rows) V.row(r++) << p[0], p[1], p[2];
  return V;
}

Eigen::MatrixXi faces(std::initializer_list<std::array<int, 3>> rows) {
  Eigen::MatrixXi F(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::Index r = 0;
  for (const auto& t : rows) F.row(r++) << t[0], t[1], t[2];
  return F;
}

/// Expects cleaning to have removed nothing: every removal count zero.
void expectNothingRemoved(const MeshCleanReport& report) {
  EXPECT_EQ(report.mergedDuplicateVertices, 0);
  EXPECT_EQ(report.droppedRepeatedIndexFaces, 0);
  EXPECT_EQ(report.droppedZeroAreaFaces, 0);
  EXPECT_EQ(report.droppedDuplicateFaces, 0);
  EXPECT_EQ(report.droppedUnreferencedVertices, 0);
}

TEST(CleanMesh, LeavesACleanClosedMeshUntouched) {
  const sc::testing::GeneratedMesh ico = sc::testing::icosphere(2);
  Eigen::MatrixXd V = ico.V;
  Eigen::MatrixXi F = ico.F;
  const MeshCleanReport report = cleanMesh(V, F);
  expectNothingRemoved(report);
  EXPECT_EQ(report.nonManifoldEdges, 0);
  EXPECT_EQ(report.boundaryLoops, 0);
  EXPECT_EQ(report.components, 1);
  EXPECT_EQ(V, ico.V);
  EXPECT_EQ(F, ico.F);
}

TEST(CleanMesh, MergesExactlyCoincidentVertices) {
  //   2=4-----3      vertices 4 and 5 repeat 2 and 1 exactly, so the two triangles
  //    |    / |      (0 1 2) and (5 3 4) become (0 1 2) and (1 3 2): one square, one boundary loop.
  //    |  /   |      Vertex 6 is −0 where vertex 0 has +0: the same position.
  //   0=6-----1=5
  Eigen::MatrixXd V = positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}, {-0.0, 0, 0}});
  Eigen::MatrixXi F = faces({{0, 1, 2}, {5, 3, 4}, {6, 3, 2}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.mergedDuplicateVertices, 3);
  EXPECT_EQ(report.droppedUnreferencedVertices, 0) << "merged vertices are not counted again as unreferenced";
  EXPECT_EQ(report.droppedDuplicateFaces, 0);
  EXPECT_EQ(V.rows(), 4);
  EXPECT_EQ(F, faces({{0, 1, 2}, {1, 3, 2}, {0, 3, 2}}));
  EXPECT_EQ(report.components, 1);
}

TEST(CleanMesh, RestoresSharedVerticesOfATriangleSoup) {
  // What a naive STL import gives: every triangle with its own three corners.
  const sc::testing::GeneratedMesh ico = sc::testing::icosphere(2);
  Eigen::MatrixXd V(3 * ico.F.rows(), 3);
  Eigen::MatrixXi F(ico.F.rows(), 3);
  for (Eigen::Index f = 0; f < ico.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      V.row(3 * f + k) = ico.V.row(ico.F(f, k));
      F(f, k) = static_cast<int>(3 * f + k);
    }
  }
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.mergedDuplicateVertices, 3 * ico.F.rows() - ico.V.rows());
  EXPECT_EQ(V.rows(), ico.V.rows());
  ASSERT_EQ(F.rows(), ico.F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(V.row(F(f, k)), ico.V.row(ico.F(f, k)));
  }
  EXPECT_EQ(report.boundaryLoops, 0);
  EXPECT_EQ(report.nonManifoldEdges, 0);
}

TEST(CleanMesh, DropsFacesWithARepeatedIndex) {
  //   2          (0 1 2) is kept; (0 1 1) names vertex 1 twice;
  //   | \        (0 3 1) has vertex 3 at vertex 1's position, so after merging it is (0 1 1) too.
  //   0--1=3
  Eigen::MatrixXd V = positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}});
  Eigen::MatrixXi F = faces({{0, 1, 2}, {0, 1, 1}, {0, 3, 1}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.mergedDuplicateVertices, 1);
  EXPECT_EQ(report.droppedRepeatedIndexFaces, 2);
  EXPECT_EQ(F, faces({{0, 1, 2}}));
  EXPECT_EQ(V.rows(), 3);
}

TEST(CleanMesh, DropsZeroAreaFacesButKeepsSlivers) {
  //   3               (0 1 3) is a proper triangle, kept.
  //   | \             (0 1 2) has three collinear corners: zero area, dropped.
  //   0--1--2         (4 5 6) is collinear up to the rounding of 3·0.1 etc.: dropped.
  //                   (0 2 7) is a sliver 1e-9 high but 2 long: a real triangle, kept.
  const Eigen::Vector3d d(0.1, 0.2, 0.3);
  Eigen::MatrixXd V =
      positions({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {5, 5, 5}, {0, 0, 0}, {0, 0, 0}, {1, 1e-9, 0}});
  V.row(5) = (V.row(4).transpose() + d).transpose();
  V.row(6) = (V.row(4).transpose() + 3 * d).transpose();
  Eigen::MatrixXi F = faces({{0, 1, 3}, {0, 1, 2}, {4, 5, 6}, {0, 2, 7}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.droppedZeroAreaFaces, 2);
  EXPECT_EQ(report.droppedRepeatedIndexFaces, 0);
  EXPECT_EQ(F.rows(), 2);
  EXPECT_EQ(report.droppedUnreferencedVertices, 3) << "vertices 4, 5 and 6 were used only by a dropped face";
}

TEST(CleanMesh, DropsDuplicateFacesInAnyOrderAndOrientation) {
  //   2---3      (0 1 2) first, then the same three vertices rotated (1 2 0) and flipped (2 1 0):
  //   | \ |      both dropped; (1 3 2) shares only an edge and stays.
  //   0---1
  Eigen::MatrixXd V = positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  Eigen::MatrixXi F = faces({{0, 1, 2}, {1, 2, 0}, {1, 3, 2}, {2, 1, 0}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.droppedDuplicateFaces, 2);
  EXPECT_EQ(F, faces({{0, 1, 2}, {1, 3, 2}})) << "the first occurrence is kept, in order";
  EXPECT_EQ(report.nonManifoldEdges, 0) << "duplicates are gone before edges are counted";
}

TEST(CleanMesh, DropsUnreferencedVerticesAndReindexes) {
  //   4          vertices 1 and 3 are used by no face;
  //   | \        (0 2 4) becomes (0 1 2).
  //   0--2   1   3
  Eigen::MatrixXd V = positions({{0, 0, 0}, {7, 7, 7}, {1, 0, 0}, {8, 8, 8}, {0, 1, 0}});
  Eigen::MatrixXi F = faces({{0, 2, 4}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.droppedUnreferencedVertices, 2);
  EXPECT_EQ(F, faces({{0, 1, 2}}));
  EXPECT_EQ(V, positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

TEST(CleanMesh, CountsNonManifoldEdges) {
  //        2   3   4      a book: three pages (0 1 2) (0 1 3) (0 1 4) on the spine 0–1,
  //         \  |  /       which is one edge with three faces. A second spine 0–5 with pages
  //          0---1        (0 5 2) … only has two faces, so it is manifold.
  Eigen::MatrixXd V = positions({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 0, 1}, {0.5, -1, 0}, {-1, 1, 1}});
  Eigen::MatrixXi F = faces({{0, 1, 2}, {0, 1, 3}, {1, 0, 4}, {0, 5, 2}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.nonManifoldEdges, 1);
  expectNothingRemoved(report);
  EXPECT_EQ(report.components, 1);
}

TEST(CleanMesh, CountsBoundaryLoops) {
  // A 3×3 grid without its middle square is an annulus: outer and inner boundary.
  //   +--+--+--+
  //   |  |  |  |
  //   +--+--+--+
  //   |  |  |  |
  //   +--+  +--+
  //   |  |  |  |
  //   +--+--+--+
  const sc::testing::GeneratedMesh grid = sc::testing::grid(3, 3);
  std::vector<int> kept;
  for (Eigen::Index f = 0; f < grid.F.rows(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) centroid += grid.V.row(grid.F(f, k)).transpose() / 3;
    const bool middle =
        centroid.x() > 1.0 / 3 && centroid.x() < 2.0 / 3 && centroid.y() > 1.0 / 3 && centroid.y() < 2.0 / 3;
    if (!middle) kept.push_back(static_cast<int>(f));
  }
  Eigen::MatrixXd V = grid.V;
  Eigen::MatrixXi F = grid.F(kept, Eigen::all);
  EXPECT_EQ(cleanMesh(V, F).boundaryLoops, 2);

  Eigen::MatrixXd V2 = grid.V;
  Eigen::MatrixXi F2 = grid.F;
  EXPECT_EQ(cleanMesh(V2, F2).boundaryLoops, 1) << "the full grid";

  //   2     5      two separate triangles:
  //   | \   | \    two loops, two components
  //   0--1  3--4
  Eigen::MatrixXd V3 = positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {2, 1, 0}});
  Eigen::MatrixXi F3 = faces({{0, 1, 2}, {3, 4, 5}});
  const MeshCleanReport two = cleanMesh(V3, F3);
  EXPECT_EQ(two.boundaryLoops, 2);
  EXPECT_EQ(two.components, 2);
}

TEST(CleanMesh, CountsComponents) {
  const sc::testing::GeneratedMesh spheres = sc::testing::twoSpheres(1);
  Eigen::MatrixXd V = spheres.V;
  Eigen::MatrixXi F = spheres.F;
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.components, 2);
  EXPECT_EQ(report.boundaryLoops, 0);
  expectNothingRemoved(report);
}

TEST(CleanMesh, ReportsEveryProblemOfOneSoup) {
  //   2=6----3      (0 1 2) (1 3 2)       the square, kept
  //    |   / |      (5 3 6)               = (1 3 2) after merging 5→1, 6→2: a duplicate
  //    | /   |      (0 0 3)               repeated index
  //   0----1=5  4   (0 1 4)-ish collinear: (0 1 7) with 7 = (2, 0, 0)
  //                 vertex 4 is unused
  Eigen::MatrixXd V =
      positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {9, 9, 9}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}});
  Eigen::MatrixXi F = faces({{0, 1, 2}, {1, 3, 2}, {5, 3, 6}, {0, 0, 3}, {0, 1, 7}});
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.mergedDuplicateVertices, 2);
  EXPECT_EQ(report.droppedRepeatedIndexFaces, 1);
  EXPECT_EQ(report.droppedZeroAreaFaces, 1);
  EXPECT_EQ(report.droppedDuplicateFaces, 1);
  EXPECT_EQ(report.droppedUnreferencedVertices, 2) << "vertex 4, and vertex 7 after its only face went";
  EXPECT_EQ(report.nonManifoldEdges, 0);
  EXPECT_EQ(report.boundaryLoops, 1);
  EXPECT_EQ(report.components, 1);
  EXPECT_EQ(F, faces({{0, 1, 2}, {1, 3, 2}}));
  EXPECT_EQ(V, positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}));
}

TEST(CleanMesh, EmptiesAMeshWithoutFaces) {
  Eigen::MatrixXd V = positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  Eigen::MatrixXi F(0, 3);
  const MeshCleanReport report = cleanMesh(V, F);
  EXPECT_EQ(report.droppedUnreferencedVertices, 3);
  EXPECT_EQ(V.rows(), 0);
  EXPECT_EQ(F.rows(), 0);
  EXPECT_EQ(report.components, 0);
  EXPECT_EQ(report.boundaryLoops, 0);
}

}  // namespace
}  // namespace sc::model
