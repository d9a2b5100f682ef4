// Tests for the client's level check and decode (src/session/engine/client_level_decode.cpp), the pure function the
// adapter's worker thread runs: checksum, decode, the session's shape, the interleaved rest positions.
#include "client_engine_fixture.h"

#include "spectral/resolution_level.h"

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
