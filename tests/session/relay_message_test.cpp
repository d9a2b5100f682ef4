// Relay messages (src/session/wire/relay_message.h, issue 18): frames and facts signed with the host's TLS
// identity key round-trip exactly; a changed byte, another session, another key or a truncation is refused without
// reading past the input.
#include "session/wire/relay_message.h"
#include "relay_test_identity.h"
#include "session/net/tls_identity.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <memory>

namespace sc::session {
namespace {

using testing::relayIdentity;

RelayFrame someFrame(int m = 20, std::uint32_t number = 7) {
  RelayFrame frame;
  frame.frame = number;
  frame.stampMicros = 123456789;
  frame.Z = Eigen::MatrixXd::Random(m, 3);
  return frame;
}

TEST(RelayMessage, SignedFrameRoundTripsExactly) {
  const RelaySigner signer(relayIdentity().privateKey.toDer(), QStringLiteral("s1"));
  ASSERT_TRUE(signer.valid());
  const RelayVerifier verifier(relayIdentity().certificate.toDer(), QStringLiteral("s1"));
  ASSERT_TRUE(verifier.valid());
  const RelayFrame frame = someFrame();
  const QByteArray message = signer.sign(encodeRelayFrameBody(frame));
  EXPECT_LE(message.size(), kRelayFrameHeaderSize + 24 * 20 + 1 + kMaxRelaySignatureBytes);
  EXPECT_EQ(relayKind(message), RelayKind::Frame);
  RelayError error = RelayError::Malformed;
  const std::optional<QByteArrayView> body = verifier.verify(message, &error);
  ASSERT_TRUE(body);
  EXPECT_EQ(error, RelayError::None);
  const std::optional<RelayFrame> decoded = decodeRelayFrameBody(*body);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->frame, frame.frame);
  EXPECT_EQ(decoded->stampMicros, frame.stampMicros);
  EXPECT_EQ(decoded->Z, frame.Z);  // exact: f64 on the wire
}

TEST(RelayMessage, AChangedByteAnotherSessionOrAnotherKeyIsRefused) {
  const RelaySigner signer(relayIdentity().privateKey.toDer(), QStringLiteral("s1"));
  const QByteArray message = signer.sign(encodeRelayFrameBody(someFrame()));
  const RelayVerifier verifier(relayIdentity().certificate.toDer(), QStringLiteral("s1"));
  for (const qsizetype at : {qsizetype{3}, qsizetype{10}, qsizetype{100}, message.size() - 5}) {
    QByteArray forged = message;
    forged[at] = static_cast<char>(forged[at] ^ 0x01);
    RelayError error = RelayError::None;
    EXPECT_FALSE(verifier.verify(forged, &error)) << at;
    EXPECT_EQ(error, RelayError::BadSignature) << at;
  }
  RelayError error = RelayError::None;
  EXPECT_FALSE(RelayVerifier(relayIdentity().certificate.toDer(), QStringLiteral("s2")).verify(message, &error));
  EXPECT_EQ(error, RelayError::BadSignature);
  EXPECT_FALSE(RelayVerifier(relayIdentity(1).certificate.toDer(), QStringLiteral("s1")).verify(message, &error));
  EXPECT_EQ(error, RelayError::BadSignature);
}

TEST(RelayMessage, EveryTruncationIsRefusedWithoutReadingPastTheInput) {
  const RelaySigner signer(relayIdentity().privateKey.toDer(), QStringLiteral("s1"));
  const QByteArray message = signer.sign(encodeRelayFrameBody(someFrame(4)));
  const RelayVerifier verifier(relayIdentity().certificate.toDer(), QStringLiteral("s1"));
  for (qsizetype size = 0; size < message.size(); ++size) {
    const QByteArray prefix = message.first(size);  // a copy: ASan sees any read past it
    EXPECT_FALSE(verifier.verify(prefix)) << size;
  }
  const std::optional<QByteArrayView> body = relayBody(message);
  ASSERT_TRUE(body);
  for (qsizetype size = 0; size < body->size(); ++size) {
    const QByteArray prefix = body->first(size).toByteArray();
    EXPECT_FALSE(decodeRelayFrameBody(prefix)) << size;
  }
}

TEST(RelayMessage, NonFiniteValuesAndWrongCountsAreMalformed) {
  RelayFrame frame = someFrame(3);
  const QByteArray good = encodeRelayFrameBody(frame);
  // A NaN written by a (hostile) signer: the encoder writes 0 instead, so patch the bytes.
  QByteArray nan = good;
  const auto bits = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::quiet_NaN());
  for (int i = 0; i < 8; ++i) nan[kRelayFrameHeaderSize + i] = static_cast<char>(bits >> (56 - 8 * i));
  EXPECT_FALSE(decodeRelayFrameBody(nan));
  EXPECT_FALSE(decodeRelayFrameBody(QByteArray(good + QByteArray(1, '\0'))));  // trailing byte
  QByteArray zeroRows = good.first(kRelayFrameHeaderSize);
  zeroRows[16] = 0;
  zeroRows[17] = 0;
  EXPECT_FALSE(decodeRelayFrameBody(zeroRows));
  frame.Z(0, 0) = std::numeric_limits<double>::infinity();
  const std::optional<RelayFrame> sanitized = decodeRelayFrameBody(encodeRelayFrameBody(frame));
  ASSERT_TRUE(sanitized);
  EXPECT_EQ(sanitized->Z(0, 0), 0.0);
  EXPECT_FALSE(relayBody(QByteArray(5, '\0')));
  QByteArray bigSignature = good + QByteArray(80, 'x');
  bigSignature.append(static_cast<char>(kMaxRelaySignatureBytes + 1));
  EXPECT_FALSE(relayBody(bigSignature));
}

TEST(RelayMessage, FactsRoundTripAndCarryTheFingerprint) {
  const RelaySigner signer(relayIdentity().privateKey.toDer(), QStringLiteral("s1"));
  RelayFacts facts;
  facts.rowCount = 100;
  facts.vertexCount = 34834;
  facts.certificateDer = relayIdentity().certificate.toDer();
  const QByteArray message = signer.sign(encodeRelayFactsBody(facts));
  EXPECT_EQ(relayKind(message), RelayKind::Facts);
  const std::optional<QByteArrayView> body = relayBody(message);
  ASSERT_TRUE(body);
  const std::optional<RelayFacts> decoded = decodeRelayFactsBody(*body);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->rowCount, 100);
  EXPECT_EQ(decoded->vertexCount, 34834u);
  EXPECT_EQ(relayCertificateFingerprint(decoded->certificateDer), relayIdentity().fingerprint());
  EXPECT_FALSE(decodeRelayFrameBody(*body));  // a Facts body is no frame
}

TEST(RelayMessage, SessionIdsAreSafeSubjectTokens) {
  EXPECT_TRUE(isValidSessionId(QStringLiteral("lecture-7_B")));
  EXPECT_FALSE(isValidSessionId(QString()));
  EXPECT_FALSE(isValidSessionId(QStringLiteral("a.b")));
  EXPECT_FALSE(isValidSessionId(QStringLiteral("a*")));
  EXPECT_FALSE(isValidSessionId(QStringLiteral("a>")));
  EXPECT_FALSE(isValidSessionId(QString(33, u'a')));
}

TEST(RelayMessage, AnUnreadableKeyCannotSign) {
  const RelaySigner signer(QByteArray("not a key"), QStringLiteral("s1"));
  EXPECT_FALSE(signer.valid());
  EXPECT_TRUE(signer.sign(QByteArray("body")).isEmpty());
  EXPECT_FALSE(RelayVerifier(QByteArray("not a certificate"), QStringLiteral("s1")).valid());
}

}  // namespace
}  // namespace sc::session
