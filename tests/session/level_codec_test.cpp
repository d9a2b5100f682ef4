// The compressed level payload (session/wire/level_codec.h): an exact round trip of the canonical bytes, smaller
// than them, and refusals of corrupted, truncated, oversized and lying payloads without allocating what they claim.

#include "session/wire/level_codec.h"
#include "session/wire/model_transfer.h"
#include "spectral/resolution_level.h"
#include "test_levels.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace sc::session {
namespace {

/// An icosphere level with a smooth basis (sines of the coordinates), P a convex mix of two vertices per row.
QByteArray canonicalLevel(int subdivisions = 3, int m = 12) {
  const Eigen::MatrixXd V = sc::testing::icosphere(subdivisions).V;
  Eigen::MatrixXd K(V.rows(), m);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int j = 0; j < m; ++j) K(i, j) = std::sin((j + 1) * V(i, j % 3) + 0.3 * j);
  const spectral::ResolutionLevel level = sc::testing::icosphereLevel(subdivisions, K);
  const std::vector<std::byte> bytes = spectral::encodeResolutionLevel(level);
  return QByteArray(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
}

TEST(LevelCodec, RoundTripIsExactAndSmaller) {
  const QByteArray canonical = canonicalLevel();
  const QByteArray compressed = compressLevelPayload(canonical);
  ASSERT_FALSE(compressed.isEmpty());
  EXPECT_LT(compressed.size(), canonical.size() * 3 / 4) << compressed.size() << " of " << canonical.size();
  EXPECT_EQ(declaredLevelPayloadSize(compressed), static_cast<std::uint64_t>(canonical.size()));
  const LevelDecompression out = decompressLevelPayload(compressed, static_cast<std::uint64_t>(canonical.size()));
  ASSERT_TRUE(out.ok()) << out.error.toStdString();
  EXPECT_EQ(out.payload, canonical);
  EXPECT_EQ(sha256(out.payload), sha256(canonical)) << "the transfer's SHA-256 is the decoded payload's";
  EXPECT_TRUE(spectral::decodeResolutionLevel(std::span(reinterpret_cast<const std::byte*>(out.payload.constData()),
                                                        static_cast<std::size_t>(out.payload.size())))
                  .ok());
}

TEST(LevelCodec, FacesTheIndexCodecWouldRotateStillRoundTrip) {
  // A level whose faces are in an order the index codec rotates (reversed) still decodes to the same bytes.
  const sc::testing::GeneratedMesh mesh = sc::testing::icosphere(2);
  spectral::ResolutionLevel level;
  level.restV = mesh.V;
  level.F = mesh.F.colwise().reverse();
  level.P.resize(mesh.V.rows(), mesh.V.rows());
  level.P.setIdentity();
  level.K = spectral::quantizeBasis(mesh.V);
  const std::vector<std::byte> bytes = spectral::encodeResolutionLevel(level);
  const QByteArray canonical(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
  const LevelDecompression out = decompressLevelPayload(compressLevelPayload(canonical), 1U << 30);
  ASSERT_TRUE(out.ok()) << out.error.toStdString();
  EXPECT_EQ(out.payload, canonical);
}

TEST(LevelCodec, NotALevelIsNotCompressed) {
  EXPECT_TRUE(compressLevelPayload(QByteArray("not a level")).isEmpty());
  QByteArray cut = canonicalLevel();
  cut.chop(1);
  EXPECT_TRUE(compressLevelPayload(cut).isEmpty());
}

TEST(LevelCodec, ALevelLargerThanTheLimitIsRefusedBeforeAllocating) {
  const QByteArray canonical = canonicalLevel();
  const QByteArray compressed = compressLevelPayload(canonical);
  const LevelDecompression small = decompressLevelPayload(compressed, static_cast<std::uint64_t>(canonical.size() - 1));
  EXPECT_FALSE(small.ok());
  EXPECT_TRUE(small.payload.isEmpty());
  EXPECT_TRUE(small.error.contains(QStringLiteral("larger than"))) << small.error.toStdString();
  // Counts of 2³² − 1 everywhere: a level of exabytes, refused from the header alone.
  QByteArray huge = compressed;
  for (int field = 12; field < 32; field += 4) std::memset(huge.data() + field, 0xff, 4);
  const LevelDecompression out = decompressLevelPayload(huge, 1U << 30);
  EXPECT_FALSE(out.ok());
  EXPECT_TRUE(out.error.contains(QStringLiteral("larger than"))) << out.error.toStdString();
}

TEST(LevelCodec, CorruptedTruncatedAndLyingPayloadsAreRefusedOrCaughtByTheChecksum) {
  const QByteArray canonical = canonicalLevel();
  const QByteArray compressed = compressLevelPayload(canonical);
  const auto limit = static_cast<std::uint64_t>(canonical.size());
  const QByteArray digest = sha256(canonical);
  // Every prefix is refused (the sections no longer fill the payload, or the header is short).
  for (qsizetype size = 0; size < compressed.size(); size += 7)
    EXPECT_FALSE(decompressLevelPayload(compressed.first(size), limit).ok()) << "prefix " << size;
  EXPECT_FALSE(decompressLevelPayload(compressed + QByteArray(1, '\0'), limit).ok()) << "a trailing byte";
  // A flipped bit anywhere: either a codec refuses it, or what decodes fails the SHA-256 of the transfer, or it was
  // in bits the codecs do not read (the payload decodes to the original: harmless).
  int refusedByCodec = 0, caughtByChecksum = 0;
  for (qsizetype at = 0; at < compressed.size(); at += 3) {
    QByteArray flipped = compressed;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x08);
    const LevelDecompression out = decompressLevelPayload(flipped, limit);
    if (!out.ok()) {
      EXPECT_FALSE(out.error.isEmpty());
      ++refusedByCodec;
    } else if (out.payload != canonical) {
      ASSERT_FALSE(checksumMatches(out.payload, digest)) << "byte " << at;
      ++caughtByChecksum;
    }
  }
  EXPECT_GT(refusedByCodec, 0);
  EXPECT_GT(caughtByChecksum, 0);
  // Wrong magic and another codec version are named.
  QByteArray magic = compressed;
  magic[0] = 'X';
  EXPECT_TRUE(decompressLevelPayload(magic, limit).error.contains(QStringLiteral("not a compressed")));
  QByteArray version = compressed;
  version[8] = 2;
  EXPECT_TRUE(decompressLevelPayload(version, limit).error.contains(QStringLiteral("codec version 2")));
  EXPECT_FALSE(declaredLevelPayloadSize(version).has_value());
}

}  // namespace
}  // namespace sc::session
