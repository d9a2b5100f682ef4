// DisplayLevel / DisplayFrame (the one-way frame path's values) and the typed vertex ids.
#include "spectral/display_level.h"
#include "spectral/vertex_ids.h"

#include <gtest/gtest.h>

#include <type_traits>

namespace sc::spectral {
namespace {

// A mixed-up id space must not compile: neither id converts to the other, nor to or from a plain integer.
static_assert(!std::is_convertible_v<FullVertexId, DisplayVertexId>);
static_assert(!std::is_convertible_v<DisplayVertexId, FullVertexId>);
static_assert(!std::is_convertible_v<std::uint32_t, FullVertexId>);
static_assert(!std::is_convertible_v<FullVertexId, std::uint32_t>);

ResolutionLevel smallLevel(int n, int m) {
  ResolutionLevel level;
  level.restV = Eigen::MatrixXd::Random(n, 3);
  level.F.resize(1, 3);
  level.F << 0, 1, 2;
  level.K = quantizeBasis(Eigen::MatrixXd::Random(n, m));
  return level;
}

TEST(DisplayLevel, KeepsTheLevelAndInterleavesItsRestPositions) {
  const ResolutionLevel level = smallLevel(5, 4);
  const SharedDisplayLevel display = makeDisplayLevel(level);
  ASSERT_EQ(display->vertexCount(), 5u);
  EXPECT_EQ(display->basisSize(), 4);
  ASSERT_EQ(display->rest.size(), 15u);
  for (int i = 0; i < 5; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(display->rest[3 * i + c], static_cast<float>(level.restV(i, c)));
  EXPECT_EQ(display->level.K, level.K);
}

TEST(DisplayLevel, ReconstructsRestPlusKTimesZ) {
  const SharedDisplayLevel display = makeDisplayLevel(smallLevel(7, 6));
  DisplayFrame frame{3, Eigen::MatrixXf::Random(6, 3)};
  const std::vector<float> out = reconstructed(*display, frame);
  const Eigen::MatrixXd expected =
      display->level.restV + dequantized(display->level.K).cast<double>() * frame.Z.cast<double>();
  ASSERT_EQ(out.size(), 21u);
  for (int i = 0; i < 7; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[3 * i + c], expected(i, c), 1e-5);
}

TEST(DisplayLevel, AnEmptyZIsTheRestShape) {
  const SharedDisplayLevel display = makeDisplayLevel(smallLevel(4, 3));
  EXPECT_EQ(reconstructed(*display, DisplayFrame{}), display->rest);
}

// What a view draws comes with the level (issue 19 item 3: built where the level is built or decoded, not on the
// thread that shows it): rest positions relative to the box centre, faces as an element buffer, rest normals, the
// box and the bounds of K that the camera's conservative box uses.
TEST(DisplayLevel, CarriesTheGeometryAViewDraws) {
  ResolutionLevel level;
  level.restV.resize(4, 3);  // a unit square in the plane z = 5, far from the origin
  level.restV << 100, 20, 5, 101, 20, 5, 101, 21, 5, 100, 21, 5;
  level.F.resize(2, 3);
  level.F << 0, 1, 2, 0, 2, 3;  // counter-clockwise seen from +z
  Eigen::MatrixXd K(4, 2);
  K << 0.5, -2, 1, 0, -3, 0.25, 0, 1;
  level.K = quantizeBasis(K);
  const SharedDisplayLevel display = makeDisplayLevel(level);
  const DisplayGeometry& g = display->geometry;
  EXPECT_EQ(g.origin, Eigen::RowVector3d(100.5, 20.5, 5.0));
  ASSERT_EQ(g.rest.size(), 12u);
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(g.rest[3 * i + c], static_cast<float>(level.restV(i, c) - g.origin(c)));
  EXPECT_EQ(g.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  ASSERT_EQ(g.normals.size(), 12u);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(Eigen::Vector3f(g.normals[3 * i], g.normals[3 * i + 1], g.normals[3 * i + 2]), Eigen::Vector3f(0, 0, 1));
  EXPECT_EQ(g.lo, Eigen::Vector3f(-0.5f, -0.5f, 0.0f));
  EXPECT_EQ(g.hi, Eigen::Vector3f(0.5f, 0.5f, 0.0f));
  const Eigen::MatrixXf Kf = dequantized(level.K);
  EXPECT_FLOAT_EQ(g.maxRowNorm, Kf.rowwise().norm().maxCoeff());
  ASSERT_EQ(g.maxAbsColumn.size(), 2);
  EXPECT_FLOAT_EQ(g.maxAbsColumn(0), Kf.col(0).cwiseAbs().maxCoeff());
  EXPECT_FLOAT_EQ(g.maxAbsColumn(1), Kf.col(1).cwiseAbs().maxCoeff());
}

// makeDisplayLevel() never reads outside the vertices: a face index out of range leaves the normals at zero (the
// client's decoder refuses such a level before; this is the wrapper's own guard).
TEST(DisplayLevel, AFaceIndexOutOfRangeLeavesTheNormalsAtZero) {
  ResolutionLevel level = smallLevel(3, 2);
  level.F << 0, 1, 7;
  const SharedDisplayLevel display = makeDisplayLevel(level);
  EXPECT_EQ(display->geometry.indices, (std::vector<std::uint32_t>{0, 1, 7}));
  EXPECT_EQ(display->geometry.normals, std::vector<float>(9, 0.0f));
}

TEST(VertexIds, ConvertToAndFromPlainIndicesInOrder) {
  const std::vector<std::uint32_t> plain{4, 0, 9};
  const DisplayVertexIds ids = vertexIds<DisplayVertexId>(plain);
  ASSERT_EQ(ids.size(), 3u);
  EXPECT_EQ(ids[0], DisplayVertexId(4));
  EXPECT_LT(ids[1], ids[0]);
  EXPECT_EQ(plainIndices<DisplayVertexTag>(ids), plain);
}

}  // namespace
}  // namespace sc::spectral
