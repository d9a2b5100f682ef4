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
