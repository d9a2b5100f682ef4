// The lock line of the session toolbar from a LockClient driven by hand-made host notices (no session).

#include "app/gui/lock_text.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <utility>
#include <vector>

namespace sc::app {
namespace {

using session::LockNotice;
using session::LockNoticeKind;
using namespace std::chrono_literals;

session::PeerList peers() {
  session::PeerList list;
  list.peers.push_back({1, 100, QStringLiteral("alice")});
  list.peers.push_back({2, 100, QStringLiteral("bob")});
  list.peers.push_back({7, 100, QString()});  // no name: "peer 7"
  return list;
}

TEST(LockText, NamesTheHolderAndWhereThisUserStands) {
  session::LockClient lock(2);
  EXPECT_EQ(lockText(lock, {}, 2, peers()), QStringLiteral("Lock free"));
  ASSERT_TRUE(lock.request(0ms).has_value());
  EXPECT_EQ(lockText(lock, {}, 2, peers()), QStringLiteral("Lock free — requesting…"));
  lock.apply({LockNoticeKind::Granted, 1, 1, 0}, 1ms);  // alice got it first
  lock.apply({LockNoticeKind::Queued, 2, session::kNoEpoch, 2}, 2ms);
  EXPECT_EQ(lockText(lock, {1}, 2, peers()), QStringLiteral("Lock held by alice — you are 2nd in the queue"));
  EXPECT_EQ(lockText(lock, {7}, 2, peers()), QStringLiteral("Lock held by peer 7 — you are 2nd in the queue"));
  lock.apply({LockNoticeKind::Granted, 2, 2, 0}, 3ms);
  ASSERT_TRUE(lock.canDrag());
  EXPECT_EQ(lockText(lock, {2}, 2, peers()), QStringLiteral("You hold the lock"));
  ASSERT_TRUE(lock.release(4ms).has_value());
  EXPECT_EQ(lockText(lock, {2}, 2, peers()), QStringLiteral("Lock held by bob — releasing…"));
}

TEST(LockText, QueuePositionsReadAsEnglishOrdinals) {
  const std::pair<std::uint32_t, const char*> cases[] = {{1, "1st"},   {3, "3rd"},   {4, "4th"},   {11, "11th"},
                                                         {12, "12th"}, {13, "13th"}, {21, "21st"}, {112, "112th"}};
  for (const auto& [position, ordinal] : cases) {
    session::LockClient lock(2);
    ASSERT_TRUE(lock.request(0ms).has_value());
    lock.apply({LockNoticeKind::Queued, 2, session::kNoEpoch, position}, 1ms);
    EXPECT_EQ(lockText(lock, {1}, 2, peers()),
              QStringLiteral("Lock held by alice — you are %1 in the queue").arg(QLatin1StringView(ordinal)));
  }
}

session::LockNotice waitingNotice(std::vector<session::PeerId> queue) {
  return {LockNoticeKind::Waiting, session::kNoPeer, session::kNoEpoch, 0, {}, std::move(queue)};
}

TEST(LockText, TheHolderSeesWhoWaits) {
  session::PeerList list = peers();
  list.peers.push_back({3, 100, QStringLiteral("carol")});
  list.peers.push_back({4, 100, QStringLiteral("dan")});
  list.peers.push_back({5, 100, QStringLiteral("erin")});
  session::LockClient lock(1);
  ASSERT_TRUE(lock.request(0ms).has_value());
  lock.apply({LockNoticeKind::Granted, 1, 1, 0}, 1ms);
  EXPECT_EQ(lockText(lock, {1}, 1, list), QStringLiteral("You hold the lock"));
  lock.apply(waitingNotice({2}), 2ms);
  EXPECT_EQ(lockText(lock, {1}, 1, list), QStringLiteral("You hold the lock — bob is waiting"));
  lock.apply(waitingNotice({2, 7}), 3ms);
  EXPECT_EQ(lockText(lock, {1}, 1, list), QStringLiteral("You hold the lock — bob and peer 7 are waiting"));
  lock.apply(waitingNotice({2, 7, 3}), 4ms);
  EXPECT_EQ(lockText(lock, {1}, 1, list), QStringLiteral("You hold the lock — bob, peer 7 and carol are waiting"));
  lock.apply(waitingNotice({2, 7, 3, 4, 5}), 5ms);
  EXPECT_EQ(lockText(lock, {1}, 1, list),
            QStringLiteral("You hold the lock — bob, peer 7, carol and 2 others are waiting"))
      << "at most kMaxWaitingNames names";
  lock.apply(waitingNotice({}), 6ms);
  EXPECT_EQ(lockText(lock, {1}, 1, list), QStringLiteral("You hold the lock"));
}

TEST(LockText, TheButtonRequestsCancelsOrReleases) {
  session::LockClient lock(2);
  EXPECT_EQ(lockActionText(lock), QStringLiteral("Request lock"));
  ASSERT_TRUE(lock.request(0ms).has_value());
  EXPECT_EQ(lockActionText(lock), QStringLiteral("Cancel request"));
  lock.apply({LockNoticeKind::Granted, 1, 1, 0}, 1ms);
  lock.apply({LockNoticeKind::Queued, 2, session::kNoEpoch, 1}, 2ms);
  EXPECT_EQ(lockActionText(lock), QStringLiteral("Cancel request")) << "queued: not \"Release lock\"";
  lock.apply({LockNoticeKind::Granted, 2, 2, 0}, 3ms);
  EXPECT_EQ(lockActionText(lock), QStringLiteral("Release lock"));
  lock.apply({LockNoticeKind::Released, 2, 2, 0, session::LockReleaseReason::RevokedByHost}, 4ms);
  EXPECT_EQ(lockActionText(lock), QStringLiteral("Request lock"));
  EXPECT_EQ(lockText(lock, {}, 2, peers()), QStringLiteral("Lock free — the host released your lock"));
  ASSERT_TRUE(lock.request(5ms).has_value());
  EXPECT_EQ(lockText(lock, {}, 2, peers()), QStringLiteral("Lock free — requesting…"));
  ASSERT_TRUE(lock.release(6ms).has_value());  // cancelled
  lock.apply({LockNoticeKind::Dequeued, 2}, 7ms);
  EXPECT_EQ(lockText(lock, {}, 2, peers()), QStringLiteral("Lock free")) << "the revocation is history";
}

}  // namespace
TEST(LockText, SeveralHoldersAreNamedAndAHolderSeesWhoDragsToo) {
  session::PeerList list = peers();
  list.peers.push_back({3, 1000, QStringLiteral("carol")});
  session::LockClient lock(2);
  EXPECT_EQ(lockText(lock, {1, 3}, 2, list), QStringLiteral("Locks held by alice and carol"));
  ASSERT_TRUE(lock.request(0ms).has_value());
  lock.apply({LockNoticeKind::Granted, 2, 4, 0}, 1ms);
  EXPECT_EQ(lockText(lock, {1, 2, 3}, 2, list), QStringLiteral("You hold the lock — alice and carol drag too"));
  EXPECT_EQ(lockText(lock, {2, 3}, 2, list), QStringLiteral("You hold the lock — carol drags too"));
}

TEST(LockText, ARefusalNamesWhoseHandleOrAnchorsItOverlaps) {
  EXPECT_EQ(refusalText({1, {1}}, peers()),
            QStringLiteral("Your handle or anchors overlap alice's: paint where nobody else holds"));
  EXPECT_TRUE(refusalText({2, {}}, peers()).startsWith(QStringLiteral("Too many handle and anchor vertices")));
}

}  // namespace sc::app
