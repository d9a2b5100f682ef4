#include "session/wire/path_open.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace sc::session {
namespace {

const QByteArray kKey(kDatagramKeySize, 'k');
const QByteArray kToken(kPathTokenSize, 't');
const DatagramMac kMac(kKey);

std::optional<PathCredentials> lookup(PeerId peer) {
  if (peer == 9) return PathCredentials{&kMac, kToken};
  return std::nullopt;
}

/// Peer 9 after the host accepted PathOpens up to `highest`.
auto lookupAfter(std::uint32_t highest) {
  return [highest](PeerId peer) -> std::optional<PathCredentials> {
    if (peer == 9) return PathCredentials{&kMac, kToken, highest};
    return std::nullopt;
  };
}

TEST(PathOpen, RoundTripAndSize) {
  const QByteArray bytes = encodePathOpen(9, kToken, 1, kKey);
  EXPECT_EQ(bytes.size(), kPathOpenSize);
  EXPECT_EQ(kPathOpenSize, 42);
  const PathOpenResult result = decodePathOpen(bytes, lookup);
  EXPECT_EQ(result.error, PathOpenError::None);
  EXPECT_EQ(result.peer, 9u);
  EXPECT_EQ(result.sequence, 1u);
  EXPECT_EQ(encodePathOpen(9, kToken, 1, kKey), bytes);  // deterministic: a recording is byte-identical
}

TEST(PathOpen, SequenceIsBigEndianAfterTheTokenAndCoveredByTheTag) {
  const QByteArray bytes = encodePathOpen(9, kToken, 0x01020304u, kKey);
  EXPECT_EQ(bytes.mid(6, kPathTokenSize), kToken);
  EXPECT_EQ(bytes.mid(22, 4), QByteArray("\x01\x02\x03\x04", 4));
  const PathOpenResult result = decodePathOpen(bytes, lookup);
  ASSERT_EQ(result.error, PathOpenError::None);
  EXPECT_EQ(result.sequence, 0x01020304u);
  // Raising the sequence of a recorded PathOpen breaks its tag.
  QByteArray raised = encodePathOpen(9, kToken, 5, kKey);
  raised[25] = static_cast<char>(6);
  EXPECT_EQ(decodePathOpen(raised, lookupAfter(5)).error, PathOpenError::BadTag);
}

TEST(PathOpen, OnlyASequenceAboveTheHighestAcceptedIsFresh) {
  const auto highest = lookupAfter(5);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, 0, kKey), lookup).error, PathOpenError::Replayed);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, 1, kKey), highest).error, PathOpenError::Replayed);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, 5, kKey), highest).error, PathOpenError::Replayed);
  const PathOpenResult fresh = decodePathOpen(encodePathOpen(9, kToken, 6, kKey), highest);
  EXPECT_EQ(fresh.error, PathOpenError::None);
  EXPECT_EQ(fresh.peer, 9u);
  EXPECT_EQ(fresh.sequence, 6u);
  constexpr std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, kMax, kKey), highest).error, PathOpenError::None);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, kMax, kKey), lookupAfter(kMax)).error, PathOpenError::Replayed);
  EXPECT_STREQ(toString(PathOpenError::Replayed), "replayed");
}

TEST(PathOpen, SequenceIsCheckedLast) {
  // A replayed sequence never hides an earlier reason: every forgery keeps its own.
  const auto highest = lookupAfter(100);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, 1, kKey).left(kPathOpenSize - 1), highest).error,
            PathOpenError::Truncated);
  EXPECT_EQ(decodePathOpen(encodePathOpen(8, kToken, 1, kKey), highest).error, PathOpenError::Stranger);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, 1, QByteArray(32, 'x')), highest).error, PathOpenError::BadTag);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, QByteArray(16, 'u'), 1, kKey), highest).error, PathOpenError::Stranger);
}

TEST(PathOpen, EveryForgeryIsDroppedWithItsReason) {
  const QByteArray good = encodePathOpen(9, kToken, 1, kKey);
  EXPECT_EQ(decodePathOpen(good.left(kPathOpenSize - 1), lookup).error, PathOpenError::Truncated);
  EXPECT_EQ(decodePathOpen(good + 'x', lookup).error, PathOpenError::Truncated);
  EXPECT_EQ(decodePathOpen(encodePathOpen(8, kToken, 1, kKey), lookup).error, PathOpenError::Stranger);
  EXPECT_EQ(decodePathOpen(encodePathOpen(0, kToken, 1, kKey), lookup).error, PathOpenError::Stranger);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, 1, QByteArray(32, 'x')), lookup).error, PathOpenError::BadTag);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, QByteArray(16, 'u'), 1, kKey), lookup).error, PathOpenError::Stranger);
  QByteArray flipped = good;
  flipped[10] = static_cast<char>(flipped[10] ^ 1);
  EXPECT_EQ(decodePathOpen(flipped, lookup).error, PathOpenError::BadTag);
  for (int seed = 0; seed < 200; ++seed) {
    QByteArray random(kPathOpenSize, '\0');
    for (int i = 0; i < random.size(); ++i) random[i] = static_cast<char>((seed * 7919 + i * 104729) >> 3);
    random[4] = 0;
    random[5] = 9;  // a known peer: must still fail on the tag
    EXPECT_EQ(decodePathOpen(random, lookup).error, PathOpenError::BadTag);
  }
}

}  // namespace
}  // namespace sc::session
