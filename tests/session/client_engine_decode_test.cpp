// Tests for the client's level check and decode (src/session/engine/client_level_decode.cpp), the pure function the
// adapter's worker thread runs: checksum, decode, the session's shape, the interleaved rest positions and what a view
// draws (spectral::DisplayGeometry).
#include "client_engine_fixture.h"

#include "session/wire/level_codec.h"
#include "spectral/resolution_level.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace sc::session::test {
namespace {

LevelJob jobFor(const QByteArray& payload) { return LevelJob{payload, sha256(payload), kRows, kVertices}; }

TEST(ClientLevelDecode, AGoodPayloadBecomesADisplayLevel) {
  const QByteArray payload = encoded(tinyLevel(0.5f));
  const DecodedLevel out = decodeLevel(jobFor(payload));
  ASSERT_NE(out.level, nullptr) << out.error.toStdString();
  EXPECT_TRUE(out.error.isEmpty());
  EXPECT_EQ(out.payload, payload);
  EXPECT_EQ(out.level->vertexCount(), 3u);
  EXPECT_EQ(out.level->basisSize(), kRows);
  EXPECT_EQ(out.level->level.K, tinyLevel(0.5f).K);
  EXPECT_EQ(out.level->rest, (std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1})) << "X̂' interleaved";
  // What the viewport draws is decoded with the level, on the decode worker, not on the thread that shows it
  // (issue 19 item 3): the faces as an element buffer and the rest normals, here those of the face x + y + z = 1.
  EXPECT_EQ(out.level->geometry.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(out.level->geometry.normals.size(), 9u);
  for (const float c : out.level->geometry.normals) EXPECT_NEAR(c, 1.0 / std::sqrt(3.0), 1e-6);
}

TEST(ClientLevelDecode, AWrongChecksumIsRefused) {
  LevelJob job = jobFor(encoded(tinyLevel()));
  job.sha256 = sha256(QByteArray("something else"));
  const DecodedLevel out = decodeLevel(std::move(job));
  EXPECT_EQ(out.level, nullptr);
  EXPECT_TRUE(out.payload.isEmpty());
  EXPECT_EQ(out.error, QStringLiteral("model transfer failed: %1")
                           .arg(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum))));
}

TEST(ClientLevelDecode, ACompressedPayloadIsCheckedAgainstTheSha256OfWhatItDecodesTo) {
  const QByteArray canonical = encoded(tinyLevel(0.5f));
  const QByteArray compressed = compressLevelPayload(canonical);
  ASSERT_FALSE(compressed.isEmpty());
  const DecodedLevel out = decodeLevel(LevelJob{compressed, sha256(canonical), kRows, kVertices});
  ASSERT_NE(out.level, nullptr) << out.error.toStdString();
  EXPECT_EQ(out.level->level.K, tinyLevel(0.5f).K);
  EXPECT_EQ(out.payload, compressed) << "the payload as received";
  // The digest of the compressed bytes is not the transfer's: refused as a bad checksum.
  const DecodedLevel wrong = decodeLevel(LevelJob{compressed, sha256(compressed), kRows, kVertices});
  EXPECT_EQ(wrong.level, nullptr);
  EXPECT_TRUE(wrong.error.contains(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum))));
}

TEST(ClientLevelDecode, ACorruptedCompressedPayloadIsRefusedByTheCodecOrTheChecksum) {
  const QByteArray canonical = encoded(tinyLevel(0.5f));
  const QByteArray compressed = compressLevelPayload(canonical);
  bool codecRefused = false, checksumRefused = false;
  for (qsizetype at = 52; at < compressed.size(); ++at) {  // every byte after the header
    QByteArray corrupted = compressed;
    corrupted[at] = static_cast<char>(corrupted[at] ^ 0x21);
    const DecodedLevel out = decodeLevel(LevelJob{corrupted, sha256(canonical), kRows, kVertices});
    if (out.level) continue;  // the flip hit bits no codec reads: the level decoded is the original one
    EXPECT_TRUE(out.payload.isEmpty());
    codecRefused |= out.error.startsWith(QStringLiteral("bad compressed level payload: "));
    checksumRefused |= out.error.contains(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum)));
    EXPECT_TRUE(out.error.startsWith(QStringLiteral("bad compressed level payload: ")) ||
                out.error.contains(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum))))
        << out.error.toStdString();
  }
  EXPECT_TRUE(codecRefused);
  EXPECT_TRUE(checksumRefused);
  // A header declaring a level larger than the session's shape allows is refused before anything is allocated.
  QByteArray huge = compressed;
  for (int field = 12; field < 20; ++field) huge[field] = static_cast<char>(0x7f);
  const DecodedLevel out = decodeLevel(LevelJob{huge, sha256(canonical), kRows, kVertices});
  EXPECT_EQ(out.level, nullptr);
  EXPECT_TRUE(out.error.contains(QStringLiteral("larger than"))) << out.error.toStdString();
}

TEST(ClientLevelDecode, AnUndecodablePayloadIsRefused) {
  const DecodedLevel out = decodeLevel(jobFor(QByteArray("not a level")));
  EXPECT_EQ(out.level, nullptr);
  EXPECT_TRUE(out.error.startsWith(QStringLiteral("bad level payload: "))) << out.error.toStdString();
}

TEST(ClientLevelDecode, ALevelOfAnotherSessionsShapeIsRefused) {
  LevelJob job = jobFor(encoded(tinyLevel()));
  job.rowCount = kRows + 1;
  const DecodedLevel out = decodeLevel(std::move(job));
  EXPECT_EQ(out.level, nullptr);
  EXPECT_EQ(out.error, QStringLiteral("level does not match the session (m = 3, n = 3)"));
}

}  // namespace
}  // namespace sc::session::test
