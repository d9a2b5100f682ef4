// A viewer's relay rules (src/session/engine/relay_receiver.h, issue 18) on an injected clock: pinned facts, late
// join through the keyframe with the frames buffered meanwhile, latest wins, loss and stale counts, forged and
// malformed frames dropped and counted, a bounded join buffer.
#include "session/engine/relay_receiver.h"
#include "relay_test_identity.h"
#include "session/net/tls_identity.h"

#include <gtest/gtest.h>

namespace sc::session {
namespace {

using testing::relayIdentity;

const QString kSid = QStringLiteral("s1");
constexpr int kRows = 6;

QByteArray facts(int which = 0, int rows = kRows) {
  RelayFacts f;
  f.rowCount = rows;
  f.vertexCount = 42;
  f.certificateDer = relayIdentity(which).certificate.toDer();
  return RelaySigner(relayIdentity(which).privateKey.toDer(), kSid).sign(encodeRelayFactsBody(f));
}

Eigen::MatrixXd shapeOf(std::uint32_t number, int rows = kRows) {
  return Eigen::MatrixXd::Constant(rows, 3, 0.001 * number);
}

QByteArray frame(std::uint32_t number, int which = 0, int rows = kRows) {
  RelayFrame f;
  f.frame = number;
  f.stampMicros = 1000 * number;
  f.Z = shapeOf(number, rows);
  return RelaySigner(relayIdentity(which).privateKey.toDer(), kSid).sign(encodeRelayFrameBody(f));
}

Micros at(std::uint32_t number) { return Micros{1000 * number + 500}; }

TEST(RelayReceiver, LateJoinAppliesTheKeyframeThenTheNewerBufferedFrames) {
  RelayReceiver receiver(kSid, relayIdentity().fingerprint());
  for (std::uint32_t n = 5; n <= 8; ++n) EXPECT_FALSE(receiver.onFrame(frame(n), at(n)));  // buffered: no facts yet
  ASSERT_EQ(receiver.onFacts(facts()), RelayFactsStatus::None);
  EXPECT_FALSE(receiver.joined());
  ASSERT_TRUE(receiver.onKeyframe(frame(6), at(8)));
  EXPECT_TRUE(receiver.joined());
  ASSERT_EQ(receiver.frame(), 8u);
  EXPECT_EQ(receiver.coefficients(), shapeOf(8));
  const RelayViewerStats stats = receiver.stats(at(8));
  EXPECT_EQ(stats.applied, 3);  // keyframe 6, then 7 and 8
  EXPECT_EQ(stats.stale, 2);    // 5 and 6 were not newer than the keyframe
  EXPECT_EQ(stats.lost, 0);
  EXPECT_EQ(receiver.facts().vertexCount, 42u);
}

TEST(RelayReceiver, FramesBeforeTheFirstLiveOneAreNotLostAndTheKeyframeHasNoLatency) {
  RelayReceiver receiver(kSid, relayIdentity().fingerprint());
  ASSERT_EQ(receiver.onFacts(facts()), RelayFactsStatus::None);
  ASSERT_TRUE(receiver.onKeyframe(frame(3), at(40)));  // stored long ago: 39.5 ms old
  EXPECT_EQ(receiver.stats(at(40)).latencyP99Ms, 0.0);
  EXPECT_TRUE(receiver.onFrame(frame(9), at(9)));  // 4..8 were published before this viewer subscribed
  EXPECT_TRUE(receiver.onFrame(frame(11), at(11)));
  const RelayViewerStats stats = receiver.stats(at(11));
  EXPECT_EQ(stats.lost, 1);  // 10
  EXPECT_NEAR(stats.latencyP99Ms, 0.5, 1e-9);
}

TEST(RelayReceiver, LatestWinsAndSkippedFramesCountAsLost) {
  RelayReceiver receiver(kSid, relayIdentity().fingerprint());
  ASSERT_EQ(receiver.onFacts(facts()), RelayFactsStatus::None);
  receiver.startWithoutKeyframe(at(0));
  EXPECT_TRUE(receiver.onFrame(frame(1), at(1)));
  EXPECT_TRUE(receiver.onFrame(frame(2), at(2)));
  EXPECT_TRUE(receiver.onFrame(frame(5), at(5)));
  EXPECT_FALSE(receiver.onFrame(frame(3), at(5)));  // late: dropped, Z stays at 5
  EXPECT_FALSE(receiver.onFrame(frame(5), at(5)));  // repeated
  EXPECT_EQ(receiver.coefficients(), shapeOf(5));
  const RelayViewerStats stats = receiver.stats(at(5));
  EXPECT_EQ(stats.applied, 3);
  EXPECT_EQ(stats.lost, 2);  // 3 and 4 were skipped
  EXPECT_EQ(stats.stale, 2);
  EXPECT_NEAR(stats.latencyP50Ms, 0.5, 1e-9);  // each frame arrived 500 µs after its stamp
}

TEST(RelayReceiver, FramesFromAnotherKeyAreDroppedAndCounted) {
  RelayReceiver receiver(kSid, relayIdentity().fingerprint());
  ASSERT_EQ(receiver.onFacts(facts()), RelayFactsStatus::None);
  ASSERT_TRUE(receiver.onKeyframe(frame(1), at(1)));
  EXPECT_FALSE(receiver.onFrame(frame(2, /*which=*/1), at(2)));  // forged: another key
  QByteArray flipped = frame(3);
  flipped[20] = static_cast<char>(flipped[20] ^ 0x40);
  EXPECT_FALSE(receiver.onFrame(flipped, at(3)));
  EXPECT_FALSE(receiver.onFrame(QByteArray("\x53\x43\x01\x01garbage", 11), at(3)));
  EXPECT_FALSE(receiver.onFrame(frame(4, 0, kRows + 1), at(4)));  // authentic but another m
  EXPECT_EQ(receiver.coefficients(), shapeOf(1));
  const RelayViewerStats stats = receiver.stats(at(4));
  EXPECT_EQ(stats.badSignature, 2);                // another key, a flipped byte
  EXPECT_EQ(stats.malformed, 2);                   // garbage without a trailer, another m
  EXPECT_TRUE(receiver.onFrame(frame(5), at(5)));  // the host's next frame still applies
}

TEST(RelayReceiver, FactsOfAnotherCertificateAreRefused) {
  RelayReceiver pinned(kSid, relayIdentity().fingerprint());
  EXPECT_EQ(pinned.onFacts(facts(1)), RelayFactsStatus::WrongFingerprint);
  EXPECT_FALSE(pinned.hasFacts());
  EXPECT_FALSE(pinned.onKeyframe(frame(1), at(1)));
  RelayReceiver firstUse(kSid, std::nullopt);  // trust on first use, then pinned
  EXPECT_EQ(firstUse.onFacts(facts()), RelayFactsStatus::None);
  EXPECT_EQ(firstUse.fingerprint(), relayIdentity().fingerprint());
  EXPECT_EQ(firstUse.onFacts(facts(1)), RelayFactsStatus::WrongFingerprint);
  EXPECT_EQ(firstUse.onFacts(facts(0, kRows + 1)), RelayFactsStatus::Malformed);  // m cannot change
  QByteArray forged = facts();
  forged[6] = static_cast<char>(forged[6] ^ 0x01);  // vertex count changed after signing
  EXPECT_EQ(RelayReceiver(kSid, relayIdentity().fingerprint()).onFacts(forged), RelayFactsStatus::BadSignature);
}

TEST(RelayReceiver, TheJoinBufferIsBounded) {
  RelayReceiver receiver(kSid, relayIdentity().fingerprint());
  ASSERT_EQ(receiver.onFacts(facts()), RelayFactsStatus::None);
  const std::uint32_t count = kRelayJoinBuffer + 36;
  for (std::uint32_t n = 1; n <= count; ++n) receiver.onFrame(frame(n), at(n));
  receiver.startWithoutKeyframe(at(count));
  const RelayViewerStats stats = receiver.stats(at(count));
  EXPECT_EQ(stats.overflowed, 36);
  EXPECT_EQ(stats.applied, kRelayJoinBuffer);
  EXPECT_EQ(receiver.frame(), count);
}

TEST(RelayReceiver, ReceiversSharingVerificationCheckEachMessageOnceAndStillRefuseForgeries) {
  // The fan-out experiment's viewers of one process (relay_verified_messages.h): the second receiver of the same
  // bytes skips the verify, a forged or altered message is still verified (and refused), and a shared store for
  // another pin is ignored.
  auto shared = std::make_shared<RelayVerifiedMessages>(kSid, relayIdentity().fingerprint());
  RelayReceiver first(kSid, relayIdentity().fingerprint());
  RelayReceiver second(kSid, relayIdentity().fingerprint());
  first.shareVerification(shared);
  second.shareVerification(shared);
  for (RelayReceiver* receiver : {&first, &second}) {
    ASSERT_EQ(receiver->onFacts(facts()), RelayFactsStatus::None);
    receiver->startWithoutKeyframe(at(0));
  }
  const QByteArray one = frame(1);  // ECDSA signatures are randomised: the same bytes, as the broker delivers them
  EXPECT_TRUE(first.onFrame(one, at(1)));
  EXPECT_TRUE(second.onFrame(one, at(1)));
  EXPECT_EQ(shared->hits(), 1);
  EXPECT_EQ(second.coefficients(), shapeOf(1));

  QByteArray altered = frame(2);
  altered[20] = static_cast<char>(altered[20] ^ 0x01);  // not a message seen before: verified, refused
  EXPECT_FALSE(second.onFrame(altered, at(2)));
  EXPECT_FALSE(second.onFrame(frame(2, /*which=*/1), at(2)));  // signed by another key
  EXPECT_EQ(second.stats(at(2)).badSignature, 2);
  EXPECT_EQ(shared->hits(), 1);

  auto other = std::make_shared<RelayVerifiedMessages>(kSid, relayIdentity(1).fingerprint());
  const QByteArray forged = frame(3, /*which=*/1);
  other->remember(forged);  // a store for another host's pin does not apply to this receiver
  RelayReceiver third(kSid, relayIdentity().fingerprint());
  third.shareVerification(other);
  ASSERT_EQ(third.onFacts(facts()), RelayFactsStatus::None);
  third.startWithoutKeyframe(at(0));
  EXPECT_FALSE(third.onFrame(forged, at(3)));
  EXPECT_EQ(third.stats(at(3)).badSignature, 1);
  EXPECT_EQ(other->hits(), 0);
}

}  // namespace
}  // namespace sc::session
