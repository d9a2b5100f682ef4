#include "session/path_open.h"

#include <gtest/gtest.h>

namespace sc::session {
namespace {

const QByteArray kKey(kDatagramKeySize, 'k');
const QByteArray kToken(kPathTokenSize, 't');

std::optional<PathCredentials> lookup(PeerId peer) {
  if (peer == 9) return PathCredentials{kKey, kToken};
  return std::nullopt;
}

TEST(PathOpen, RoundTripAndSize) {
  const QByteArray bytes = encodePathOpen(9, kToken, kKey);
  EXPECT_EQ(bytes.size(), kPathOpenSize);
  const PathOpenResult result = decodePathOpen(bytes, lookup);
  EXPECT_EQ(result.error, PathOpenError::None);
  EXPECT_EQ(result.peer, 9u);
}

TEST(PathOpen, EveryForgeryIsDroppedWithItsReason) {
  const QByteArray good = encodePathOpen(9, kToken, kKey);
  EXPECT_EQ(decodePathOpen(good.left(kPathOpenSize - 1), lookup).error, PathOpenError::Truncated);
  EXPECT_EQ(decodePathOpen(good + 'x', lookup).error, PathOpenError::Truncated);
  EXPECT_EQ(decodePathOpen(encodePathOpen(8, kToken, kKey), lookup).error, PathOpenError::Stranger);
  EXPECT_EQ(decodePathOpen(encodePathOpen(0, kToken, kKey), lookup).error, PathOpenError::Stranger);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, kToken, QByteArray(32, 'x')), lookup).error, PathOpenError::BadTag);
  EXPECT_EQ(decodePathOpen(encodePathOpen(9, QByteArray(16, 'u'), kKey), lookup).error, PathOpenError::Stranger);
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
