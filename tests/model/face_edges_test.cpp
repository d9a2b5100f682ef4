// Tests for src/model/face_edges.cpp: directed edges, the faces a halfedge mesh refuses, nearest kept vertices.

#include "model/face_edges.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace sc::model::detail {
namespace {

//   3 ─── 2        faces (0 1 2) and (0 2 3), both counter-clockwise: 0→2 and 2→0 are each used once.
//   │ ╲   │
//   │   ╲ │
//   0 ─── 1
Eigen::MatrixXi square() {
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  return F;
}

TEST(FaceEdges, OutgoingEdgesListEachCornerOnceInFaceOrder) {
  const OutgoingEdges edges = outgoingEdges(4, square());
  ASSERT_EQ(edges.offsets, (std::vector<int>{0, 2, 3, 5, 6}));
  EXPECT_EQ(edges.targets[0], 1) << "0→1 of face 0 first";
  EXPECT_EQ(edges.faces[0], 0);
  EXPECT_EQ(edges.targets[1], 2) << "then 0→2 of face 1";
  EXPECT_EQ(edges.faces[1], 1);
}

TEST(FaceEdges, AConsistentMeshRefusesNothing) {
  const auto sphere = testing::icosphere(2);
  const std::vector<char> refused = refusedFaces(sphere.F, outgoingEdges(sphere.V.rows(), sphere.F));
  EXPECT_EQ(std::count(refused.begin(), refused.end(), 1), 0);
}

TEST(FaceEdges, ThirdFaceOnAnEdgeFlippedNeighbourAndRepeatedCornerAreRefused) {
  Eigen::MatrixXi F(6, 3);
  F << 0, 1, 2,  // 0→1 1→2 2→0: accepted
      0, 2, 3,   // 0→2 (face 0 has 2→0) 2→3 3→0: accepted
      0, 2, 4,   // a third face on edge 0–2, 0→2 again: refused
      1, 0, 5,   // 1→0 0→5 5→1: accepted
      2, 1, 4,   // 2→1 1→4 4→2 (4→2 only was in refused face 2): accepted
      3, 3, 1;   // repeated corner: refused
  const std::vector<char> refused = refusedFaces(F, outgoingEdges(6, F));
  EXPECT_EQ(refused, (std::vector<char>{0, 0, 1, 0, 0, 1}));
  Eigen::MatrixXi flipped(2, 3);
  flipped << 0, 1, 2, 0, 1, 3;  // both use 0→1: the second face is oriented against the first
  EXPECT_EQ(refusedFaces(flipped, outgoingEdges(4, flipped)), (std::vector<char>{0, 1}));
}

TEST(FaceEdges, MovedToKeptFollowsTheEdgesOfAcceptedFacesAndAvoidsSharedVertices) {
  const auto grid = testing::grid(5, 1);  // 2 rows of 6 vertices, row-major: 0 and 5 end the first row
  const OutgoingEdges edges = outgoingEdges(grid.V.rows(), grid.F);
  const std::vector<char> none(static_cast<std::size_t>(grid.F.rows()), 0);
  std::vector<char> kept(static_cast<std::size_t>(grid.V.rows()), 0);
  kept[0] = kept[5] = 1;
  // 1 reaches 0 in two hops (1→7→0) and no other kept vertex as soon; 4 reaches 5 in one.
  EXPECT_EQ(movedToKept({{0, 1, 4}}, kept, edges, none), (std::vector<std::array<int, 3>>{{0, 0, 5}}))
      << "a kept corner stays; the others go to the nearest kept vertex, even one the face already uses";
  // With 6 kept too, 7 has two kept vertices one hop away (7→0, 7→6); the face already uses 0, so 7 goes to 6.
  kept[6] = 1;
  EXPECT_EQ(movedToKept({{0, 7, 5}}, kept, edges, none), (std::vector<std::array<int, 3>>{{0, 6, 5}}));
  const std::vector<char> all(static_cast<std::size_t>(grid.F.rows()), 1);
  EXPECT_EQ(movedToKept({{1, 2, 3}}, kept, edges, all), (std::vector<std::array<int, 3>>{{1, 2, 3}}))
      << "no accepted face: they stay";
}

}  // namespace
}  // namespace sc::model::detail
