// The relay's signed level list (src/session/wire/relay_level_list.h, issue 18 item 1): it round-trips exactly once
// signed; every truncation, an out-of-order or out-of-range entry and impossible sizes are refused; a changed byte
// fails the signature; the chunk arithmetic covers a payload exactly.
#include "session/wire/relay_level_list.h"
#include "relay_test_identity.h"
#include "session/net/tls_identity.h"
#include "session/wire/relay_message.h"

#include <gtest/gtest.h>

#include <QtCore/QCryptographicHash>

#include <cstdint>

namespace sc::session {
namespace {

using testing::relayIdentity;

RelayLevelList someList() {
  RelayLevelList list;
  list.rowCount = 20;
  list.vertexCount = 162;
  list.chunkBytes = 4096;
  list.total = 4;
  for (std::uint8_t i : {std::uint8_t{0}, std::uint8_t{2}, std::uint8_t{3}}) {
    RelayLevelEntry entry;
    entry.index = i;
    entry.vertexCount = 162u >> i;
    entry.faceCount = 320u >> i;
    entry.payloadBytes = 10000u + i;
    entry.payloadSha256 = QCryptographicHash::hash(QByteArray(1, static_cast<char>(i)), QCryptographicHash::Sha256);
    entry.canonicalSha256 = QCryptographicHash::hash(QByteArray(2, static_cast<char>(i)), QCryptographicHash::Sha256);
    list.levels.push_back(entry);
  }
  return list;
}

TEST(RelayLevelList, SignedListRoundTripsExactly) {
  const RelaySigner signer(relayIdentity().privateKey.toDer(), QStringLiteral("s1"));
  const RelayVerifier verifier(relayIdentity().certificate.toDer(), QStringLiteral("s1"));
  const RelayLevelList list = someList();
  const QByteArray message = signer.sign(encodeRelayLevelListBody(list));
  EXPECT_EQ(relayKind(message), RelayKind::Levels);
  const std::optional<QByteArrayView> body = verifier.verify(message);
  ASSERT_TRUE(body);
  EXPECT_EQ(body->size(), kRelayLevelsHeaderSize + 3 * kRelayLevelEntrySize);
  const std::optional<RelayLevelList> decoded = decodeRelayLevelListBody(*body);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(*decoded, list);
  ASSERT_NE(decoded->find(2), nullptr);
  EXPECT_EQ(decoded->find(2)->vertexCount, 40u);
  EXPECT_EQ(decoded->find(1), nullptr);
}

TEST(RelayLevelList, AChangedByteFailsTheSignatureAndAnotherSessionToo) {
  const RelaySigner signer(relayIdentity().privateKey.toDer(), QStringLiteral("s1"));
  const QByteArray message = signer.sign(encodeRelayLevelListBody(someList()));
  const RelayVerifier verifier(relayIdentity().certificate.toDer(), QStringLiteral("s1"));
  for (const qsizetype at : {qsizetype{5}, qsizetype{20}, qsizetype{kRelayLevelsHeaderSize + 13}}) {
    QByteArray changed = message;
    changed[at] = static_cast<char>(changed[at] ^ 0x01);
    RelayError error = RelayError::None;
    EXPECT_FALSE(verifier.verify(changed, &error)) << at;
    EXPECT_EQ(error, RelayError::BadSignature) << at;
  }
  const RelayVerifier other(relayIdentity().certificate.toDer(), QStringLiteral("s2"));
  EXPECT_FALSE(other.verify(message));
}

TEST(RelayLevelList, EveryTruncationAndImpossibleFieldIsRefused) {
  const QByteArray body = encodeRelayLevelListBody(someList());
  for (qsizetype size = 0; size < body.size(); ++size) {
    EXPECT_FALSE(decodeRelayLevelListBody(QByteArrayView(body).first(size))) << size;
  }
  EXPECT_FALSE(decodeRelayLevelListBody(body + QByteArray(1, '\0')));
  const auto refused = [](const RelayLevelList& list) {
    return !decodeRelayLevelListBody(encodeRelayLevelListBody(list));
  };
  RelayLevelList list = someList();
  std::swap(list.levels[0], list.levels[1]);  // not ascending
  EXPECT_TRUE(refused(list));
  list = someList();
  list.levels[2].index = 4;  // ≥ total
  EXPECT_TRUE(refused(list));
  list = someList();
  list.total = 2;  // fewer than listed
  EXPECT_TRUE(refused(list));
  list = someList();
  list.chunkBytes = kMaxRelayChunkBytes + 1;
  EXPECT_TRUE(refused(list));
  list = someList();
  list.chunkBytes = 0;
  EXPECT_TRUE(refused(list));
  list = someList();
  list.levels[1].payloadBytes = 0;
  EXPECT_TRUE(refused(list));
  list = someList();
  list.rowCount = 0;
  EXPECT_TRUE(refused(list));
  list = someList();
  list.levels.clear();  // an empty list is well formed (the host has published nothing yet)
  EXPECT_FALSE(refused(list));
}

TEST(RelayLevelList, ChunksCoverAPayloadExactly) {
  for (const std::uint32_t bytes : {1u, 4095u, 4096u, 4097u, 12288u, 1000003u}) {
    const std::uint32_t count = relayChunkCount(bytes, 4096);
    std::uint64_t sum = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t size = relayChunkSize(bytes, 4096, i);
      EXPECT_GE(size, 1u);
      EXPECT_TRUE(i + 1 == count || size == 4096u);
      sum += size;
    }
    EXPECT_EQ(sum, bytes);
    EXPECT_EQ(relayChunkSize(bytes, 4096, count), 0u);
  }
  EXPECT_EQ(relayLevelChunkSubject(QStringLiteral("abc"), 2, 17), "sc.abc.level.2.17");
  EXPECT_EQ(relayLevelStream(QStringLiteral("abc")), "SC_abc_LEVELS");
}

}  // namespace
}  // namespace sc::session
