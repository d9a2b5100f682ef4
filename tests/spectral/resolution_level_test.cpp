#include "spectral/resolution_level.h"

#include "model/mesh_decimation.h"
#include "spectral/closest_point.h"
#include "spectral/harmonic_basis.h"
#include "spectral/level_vertex_map.h"
#include "spectral/quantized_basis.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/vertex_ids.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>

namespace sc::spectral {
namespace {

/// A torus, its basis and a decimated level: built once for the suite.
class ResolutionLevelTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_mesh = new testing::GeneratedMesh(testing::torus(60, 24));
    BasisOptions options;
    options.m = 40;
    const BasisResult r = manifoldHarmonicBasis(laplaceOperators(s_mesh->V, s_mesh->F), options);
    ASSERT_TRUE(r.ok()) << r.message;
    s_H = new Eigen::MatrixXd(r.basis.vectors);
    const model::DecimatedMesh low = model::decimateMesh(s_mesh->V, s_mesh->F, 300);
    s_level = new ResolutionLevel(resolutionLevel(s_mesh->V, s_mesh->F, *s_H, low.V, low.F));
  }
  static void TearDownTestSuite() {
    delete s_level;
    delete s_H;
    delete s_mesh;
  }
  static inline testing::GeneratedMesh* s_mesh = nullptr;
  static inline Eigen::MatrixXd* s_H = nullptr;
  static inline ResolutionLevel* s_level = nullptr;
};

TEST_F(ResolutionLevelTest, RowsOfPAreConvexWeightsOfOneFace) {
  const BarycentricMap& P = s_level->P;
  ASSERT_EQ(P.rows(), s_level->restV.rows());
  ASSERT_EQ(P.cols(), s_mesh->V.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    double sum = 0;
    int count = 0;
    for (BarycentricMap::InnerIterator it(P, i); it; ++it, ++count) {
      EXPECT_GT(it.value(), 0.0);
      sum += it.value();
    }
    EXPECT_LE(count, 3);
    EXPECT_NEAR(sum, 1.0, 1e-15) << "row " << i;
  }
}

TEST_F(ResolutionLevelTest, PTimesRestIsTheClosestPointProjection) {
  Eigen::VectorXd distances;
  const BarycentricMap P = barycentricMap(s_mesh->V, s_mesh->F, s_level->restV, &distances);
  const Eigen::MatrixXd projected = P * s_mesh->V;
  const Eigen::VectorXd offsets = (projected - s_level->restV).rowwise().norm();
  EXPECT_LT((offsets - distances).cwiseAbs().maxCoeff(), 1e-14);
  // The decimated vertices lie near the surface: within 1% of the bbox diagonal (≈ 2.9).
  EXPECT_LT(distances.maxCoeff(), 0.03);
}

TEST_F(ResolutionLevelTest, QueriesOnAndOffTheMeshVerticesMapToTheirClosestPoints) {
  // Every other query is a mesh vertex (mapped directly), the others are off the surface (mapped through the tree);
  // both must agree with the exact closest points.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  Eigen::MatrixXd Q(200, 3);
  for (Eigen::Index i = 0; i < Q.rows(); ++i) {
    Q.row(i) = s_mesh->V.row((37 * i) % s_mesh->V.rows());
    if (i % 2 == 1)
      for (int c = 0; c < 3; ++c) Q(i, c) += offset(rng);
  }
  Eigen::VectorXd distances;
  const BarycentricMap P = barycentricMap(s_mesh->V, s_mesh->F, Q, &distances);
  const ClosestPoints exact = closestPoints(s_mesh->V, s_mesh->F, Q);
  const Eigen::MatrixXd projected = P * s_mesh->V;
  EXPECT_LT((projected - exact.points).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((distances - exact.distances).cwiseAbs().maxCoeff(), 1e-14);
  for (Eigen::Index i = 0; i < Q.rows(); i += 2) {
    ASSERT_EQ(P.row(i).nonZeros(), 1) << "query " << i;
    EXPECT_EQ(P.coeff(i, (37 * i) % s_mesh->V.rows()), 1.0) << "query " << i;
    EXPECT_EQ(distances(i), 0.0);
  }
}

TEST_F(ResolutionLevelTest, KIsPTimesHQuantisedPerColumn) {
  const Eigen::MatrixXd expected = s_level->P * *s_H;
  const Eigen::MatrixXd K = dequantized(s_level->K).cast<double>();
  for (Eigen::Index j = 0; j < K.cols(); ++j) {
    const double top = expected.col(j).cwiseAbs().maxCoeff();
    // half a quantisation step, plus float32 rounding of scale·Q
    EXPECT_LE((K.col(j) - expected.col(j)).cwiseAbs().maxCoeff(), top / (2.0 * kQuantizedBasisLevels) + 2e-7 * top)
        << "column " << j;
  }
}

TEST_F(ResolutionLevelTest, LevelReconstructsTheFullDeformationMappedByP) {
  // Random smooth displacement coefficients (decaying with frequency).
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd Z(s_H->cols(), 3);
  for (Eigen::Index k = 0; k < Z.rows(); ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = normal(rng) / (1.0 + k);
  const Eigen::MatrixXd full = s_mesh->V + *s_H * Z;
  // Client: X̂' + K Z with the kernel on the quantised K. Reference: P(X̂ + H Z) plus the projection offset
  // X̂' − P X̂; the difference is float rounding plus at most the quantisation bound.
  std::vector<float> out(3 * static_cast<std::size_t>(s_level->restV.rows()));
  reconstructInterleaved(s_level->K, interleavedPositions(s_level->restV), Z.cast<float>(), out);
  const Eigen::MatrixXd expected = s_level->P * full + (s_level->restV - s_level->P * s_mesh->V);
  const double scale = full.cwiseAbs().maxCoeff();
  const double tolerance = 1e-5 * scale + quantizationBound(s_level->K, Z.cast<float>());
  for (Eigen::Index i = 0; i < expected.rows(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(out[static_cast<std::size_t>(3 * i + c)], expected(i, c), tolerance) << "vertex " << i;
}

TEST_F(ResolutionLevelTest, SerialisationRoundTripIsBitExact) {
  const std::vector<std::byte> bytes = encodeResolutionLevel(*s_level);
  const LevelDecodeResult decoded = decodeResolutionLevel(bytes);
  ASSERT_TRUE(decoded.ok()) << decoded.message;
  const ResolutionLevel& level = *decoded.level;
  EXPECT_EQ(level.restV, s_level->restV);
  EXPECT_EQ(level.F, s_level->F);
  EXPECT_EQ(level.K, s_level->K);
  EXPECT_EQ(Eigen::MatrixXd(level.P), Eigen::MatrixXd(s_level->P));
  EXPECT_EQ(encodeResolutionLevel(level), bytes);
}

TEST_F(ResolutionLevelTest, FullResolutionLevelIsTheIdentityMapAndRoundTrips) {
  const ResolutionLevel full = fullResolutionLevel(s_mesh->V, s_mesh->F, *s_H);
  EXPECT_EQ(full.P.nonZeros(), s_mesh->V.rows());
  EXPECT_EQ(Eigen::MatrixXd(full.P * s_mesh->V), s_mesh->V);
  EXPECT_EQ(full.K, quantizeBasis(*s_H));
  const LevelDecodeResult decoded = decodeResolutionLevel(encodeResolutionLevel(full));
  ASSERT_TRUE(decoded.ok()) << decoded.message;
  EXPECT_EQ(decoded.level->restV, s_mesh->V);
  EXPECT_EQ(decoded.level->F, s_mesh->F);
  EXPECT_EQ(decoded.level->K, full.K);
}

TEST_F(ResolutionLevelTest, TruncatedLongAndCorruptedBuffersAreRejected) {
  const std::vector<std::byte> bytes = encodeResolutionLevel(*s_level);
  for (std::size_t size = 0; size < bytes.size(); ++size)
    ASSERT_FALSE(decodeResolutionLevel(std::span(bytes).first(size)).ok()) << "prefix " << size;
  std::vector<std::byte> longer = bytes;
  longer.push_back(std::byte{0});
  EXPECT_EQ(decodeResolutionLevel(longer).status, LevelDecodeStatus::BadSize);
  for (std::size_t at = 0; at < bytes.size(); at += 97) {
    std::vector<std::byte> flipped = bytes;
    flipped[at] ^= std::byte{0x10};
    ASSERT_FALSE(decodeResolutionLevel(flipped).ok()) << "flipped byte " << at;
  }
  std::vector<std::byte> version = bytes;
  version[8] = std::byte{1};  // level format 1: float32 K
  EXPECT_EQ(decodeResolutionLevel(version).status, LevelDecodeStatus::UnsupportedVersion);
}

TEST_F(ResolutionLevelTest, GarbageAndHugeDeclaredSizesAreRejectedWithoutAllocating) {
  std::mt19937 rng(1);
  std::vector<std::byte> garbage(5000);
  for (std::byte& b : garbage) b = static_cast<std::byte>(rng());
  EXPECT_EQ(decodeResolutionLevel(garbage).status, LevelDecodeStatus::BadMagic);
  std::vector<std::byte> huge = encodeResolutionLevel(*s_level);
  const std::uint32_t max = 0xffffffffU;
  for (std::size_t field = 12; field < 32; field += 4) std::memcpy(huge.data() + field, &max, 4);
  EXPECT_EQ(decodeResolutionLevel(huge).status, LevelDecodeStatus::Truncated);
}

TEST_F(ResolutionLevelTest, IndicesOutOfRangeAreBadContentEvenWithAValidChecksum) {
  ResolutionLevel broken = *s_level;
  broken.F(0, 1) = static_cast<int>(broken.restV.rows());
  EXPECT_EQ(decodeResolutionLevel(encodeResolutionLevel(broken)).status, LevelDecodeStatus::BadContent);
}

TEST_F(ResolutionLevelTest, NonFiniteNumbersAreBadContentEvenWithAValidChecksum) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ResolutionLevel position = *s_level;
  position.restV(0, 2) = nan;
  EXPECT_EQ(decodeResolutionLevel(encodeResolutionLevel(position)).status, LevelDecodeStatus::BadContent);
  ResolutionLevel weight = *s_level;
  weight.P.valuePtr()[0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(decodeResolutionLevel(encodeResolutionLevel(weight)).status, LevelDecodeStatus::BadContent);
  ResolutionLevel basis = *s_level;
  basis.K.scale(0) = std::numeric_limits<float>::infinity();
  EXPECT_EQ(decodeResolutionLevel(encodeResolutionLevel(basis)).status, LevelDecodeStatus::BadContent);
  ResolutionLevel negative = *s_level;
  negative.K.scale(0) = -1.0f;
  EXPECT_EQ(decodeResolutionLevel(encodeResolutionLevel(negative)).status, LevelDecodeStatus::BadContent);
  EXPECT_TRUE(decodeResolutionLevel(encodeResolutionLevel(*s_level)).ok());
}

TEST(DominantFullVertices, PicksTheLargestWeightOfEachRowSortedAndUnique) {
  // 4 low-res vertices on 5 full-res vertices; row 3 is empty.
  BarycentricMap P(4, 5);
  std::vector<Eigen::Triplet<double>> weights{{0, 0, 0.2}, {0, 3, 0.7}, {0, 4, 0.1}, {1, 1, 0.5},
                                              {1, 2, 0.5}, {2, 3, 0.6}, {2, 2, 0.4}};
  P.setFromTriplets(weights.begin(), weights.end());
  // 2 and 0 both map to 3; 3 has no weights; 4 and 1000 are out of range
  const DisplayVertexIds low = vertexIds<DisplayVertexId>(std::vector<std::uint32_t>{2, 0, 1, 3, 4, 1000});
  // the tie in row 1 takes the first column
  EXPECT_EQ(dominantFullVertices(P, low), vertexIds<FullVertexId>(std::vector<std::uint32_t>{1, 3}));
  EXPECT_TRUE(dominantFullVertices(P, DisplayVertexIds{}).empty());
}

TEST_F(ResolutionLevelTest, DominantFullVerticesOfTheFullLevelAreTheIdsThemselves) {
  const ResolutionLevel full = fullResolutionLevel(s_mesh->V, s_mesh->F, *s_H);
  const DisplayVertexIds ids = vertexIds<DisplayVertexId>(std::vector<std::uint32_t>{7, 3, 3, 11});
  EXPECT_EQ(dominantFullVertices(full.P, ids), vertexIds<FullVertexId>(std::vector<std::uint32_t>{3, 7, 11}));
  // on a decimated level every id is a corner of the closest full-res face: within range
  DisplayVertexIds all;
  for (Eigen::Index i = 0; i < s_level->P.rows(); ++i) all.emplace_back(static_cast<std::uint32_t>(i));
  const FullVertexIds mapped = dominantFullVertices(s_level->P, all);
  EXPECT_FALSE(mapped.empty());
  for (const FullVertexId id : mapped) EXPECT_LT(id.index(), static_cast<std::size_t>(s_mesh->V.rows()));
}

// Issue 15: a client's handle and anchors are full ids and must show again on whichever level it displays.
TEST_F(ResolutionLevelTest, FullVerticesShowAgainOnTheirLevelAndAsTheNearestVerticesOnACoarserOne) {
  const ResolutionLevel full = fullResolutionLevel(s_mesh->V, s_mesh->F, *s_H);
  // the full level: the same ids, lying at their rows of V
  const LocatedFullVertices few =
      locateFullVertices(full, vertexIds<DisplayVertexId>(std::vector<std::uint32_t>{11, 3, 7, 3}));
  EXPECT_EQ(few.ids, vertexIds<FullVertexId>(std::vector<std::uint32_t>{3, 7, 11}));
  ASSERT_EQ(few.points.rows(), 3);
  EXPECT_EQ(Eigen::RowVector3d(few.points.row(1)), Eigen::RowVector3d(s_mesh->V.row(7)));
  EXPECT_EQ(displayedVertices(full, few), vertexIds<DisplayVertexId>(std::vector<std::uint32_t>{3, 7, 11}));

  // a region painted at full resolution, shown on the decimated level (300 of 1,440 vertices)
  DisplayVertexIds painted;
  for (Eigen::Index i = 0; i < s_mesh->V.rows(); ++i)
    if (s_mesh->V(i, 0) > 1.15) painted.emplace_back(static_cast<std::uint32_t>(i));
  const LocatedFullVertices region = locateFullVertices(full, painted);
  ASSERT_EQ(region.ids.size(), painted.size());
  const DisplayVertexIds shown = displayedVertices(*s_level, region);
  ASSERT_FALSE(shown.empty());
  EXPECT_TRUE(std::is_sorted(shown.begin(), shown.end()));
  const double spacing = 4.0 * std::sqrt(4.0 * 3.14159 * 3.14159 * 0.3 / 300.0);  // a few coarse edge lengths
  for (const DisplayVertexId d : shown)
    EXPECT_GT(s_level->restV(static_cast<Eigen::Index>(d.index()), 0), 1.15 - spacing);
  // every displayed vertex that stands for one of the ids is there, and each id has a displayed vertex near it
  for (Eigen::Index i = 0; i < s_level->P.rows(); ++i) {
    const DisplayVertexId d(static_cast<std::uint32_t>(i));
    const std::optional<FullVertexId> f = dominantFullVertex(s_level->P, d);
    if (f && std::binary_search(region.ids.begin(), region.ids.end(), *f)) {
      EXPECT_TRUE(std::binary_search(shown.begin(), shown.end(), d)) << i;
    }
  }
  for (Eigen::Index k = 0; k < region.points.rows(); ++k) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const DisplayVertexId d : shown)
      nearest =
          std::min(nearest, (s_level->restV.row(static_cast<Eigen::Index>(d.index())) - region.points.row(k)).norm());
    EXPECT_LT(nearest, spacing) << "full id " << region.ids[static_cast<std::size_t>(k)].value;
  }
  // without points only the exact ones; and back at full resolution, exactly what was painted
  const DisplayVertexIds exact = displayedVertices(*s_level, {region.ids, {}});
  EXPECT_LT(exact.size(), shown.size());
  EXPECT_TRUE(std::includes(shown.begin(), shown.end(), exact.begin(), exact.end()));
  EXPECT_EQ(displayedVertices(full, region), painted);
}

}  // namespace
}  // namespace sc::spectral
