// Tests for src/session/engine/lock_arbiter.cpp: the host's edit-lock state machine, without sockets.
#include "session/engine/lock_arbiter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace sc::session {
namespace {

using namespace std::chrono_literals;

constexpr PeerId kA = 1;
constexpr PeerId kB = 2;
constexpr PeerId kC = 3;

LockMessage requestMsg() { return {LockRequestKind::Request, kNoEpoch}; }
LockMessage releaseMsg(LockEpoch epoch) { return {LockRequestKind::Release, epoch}; }
LockMessage renewMsg(LockEpoch epoch) { return {LockRequestKind::Renew, epoch}; }

LockEvent grantedAll(PeerId peer, LockEpoch epoch) {
  return {LockAudience::AllPeers, kNoPeer, {LockNoticeKind::Granted, peer, epoch}};
}
LockEvent releasedAll(PeerId peer, LockEpoch epoch, LockReleaseReason reason) {
  return {LockAudience::AllPeers, kNoPeer, {LockNoticeKind::Released, peer, epoch, 0, reason}};
}
LockEvent queuedTo(PeerId peer, std::uint32_t position) {
  return {LockAudience::OnePeer, peer, {LockNoticeKind::Queued, peer, kNoEpoch, position}};
}

TEST(LockArbiter, TheHostRevokesTheHolderAndTheQueuesHeadGetsTheLock) {
  LockArbiter arbiter;
  EXPECT_TRUE(arbiter.revokeByHost(0ms).empty()) << "nothing to revoke while free";
  EXPECT_EQ(arbiter.ignoredMessages(), 0u) << "the host's own command is no network input";
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kB, requestMsg(), 10ms);
  EXPECT_EQ(arbiter.revokeByHost(20ms),
            (LockEvents{releasedAll(kA, 1, LockReleaseReason::RevokedByHost), grantedAll(kB, 2)}));
  EXPECT_EQ(arbiter.holder(), kB);
  EXPECT_TRUE(arbiter.queue().empty());
  EXPECT_EQ(arbiter.acceptDrag(kA, 1, 30ms), DragVerdict::NotHolder) << "the revoked holder's drags are refused";
  EXPECT_EQ(arbiter.revokeByHost(40ms), (LockEvents{releasedAll(kB, 2, LockReleaseReason::RevokedByHost)}));
  EXPECT_EQ(arbiter.holder(), kNoPeer);
}

TEST(LockArbiter, GrantsToFirstRequester) {
  LockArbiter arbiter;
  EXPECT_EQ(arbiter.holder(), kNoPeer);
  EXPECT_EQ(arbiter.handleMessage(kA, requestMsg(), 0ms), LockEvents{grantedAll(kA, 1)});
  EXPECT_EQ(arbiter.holder(), kA);
  EXPECT_EQ(arbiter.epoch(), 1u);
  EXPECT_TRUE(arbiter.queue().empty());
}

TEST(LockArbiter, ContendersQueueInFifoOrderAndReleasePassesOn) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  EXPECT_EQ(arbiter.handleMessage(kB, requestMsg(), 10ms), LockEvents{queuedTo(kB, 1)});
  EXPECT_EQ(arbiter.handleMessage(kC, requestMsg(), 20ms), LockEvents{queuedTo(kC, 2)});
  EXPECT_EQ(arbiter.holder(), kA) << "queued requests never take the lock from the holder";

  const LockEvents first = arbiter.handleMessage(kA, releaseMsg(1), 30ms);
  EXPECT_EQ(first, (LockEvents{releasedAll(kA, 1, LockReleaseReason::Released), grantedAll(kB, 2)}));
  const LockEvents second = arbiter.handleMessage(kB, releaseMsg(2), 40ms);
  EXPECT_EQ(second, (LockEvents{releasedAll(kB, 2, LockReleaseReason::Released), grantedAll(kC, 3)}));
  const LockEvents third = arbiter.handleMessage(kC, releaseMsg(3), 50ms);
  EXPECT_EQ(third, LockEvents{releasedAll(kC, 3, LockReleaseReason::Released)});
  EXPECT_EQ(arbiter.holder(), kNoPeer);
}

TEST(LockArbiter, ReRequestIsIdempotent) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kB, requestMsg(), 0ms);
  arbiter.handleMessage(kC, requestMsg(), 0ms);
  const LockEvent repeatGrant{LockAudience::OnePeer, kA, {LockNoticeKind::Granted, kA, 1}};
  EXPECT_EQ(arbiter.handleMessage(kA, requestMsg(), 5ms), LockEvents{repeatGrant});
  EXPECT_EQ(arbiter.handleMessage(kB, requestMsg(), 5ms), LockEvents{queuedTo(kB, 1)});
  EXPECT_EQ(arbiter.handleMessage(kC, requestMsg(), 5ms), LockEvents{queuedTo(kC, 2)});
  EXPECT_EQ(arbiter.epoch(), 1u);
  EXPECT_EQ(arbiter.queue(), (std::deque<PeerId>{kB, kC}));
}

TEST(LockArbiter, SilentHolderIsRevokedAfterLeaseAndLockPassesOn) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kB, requestMsg(), 100ms);
  EXPECT_TRUE(arbiter.tick(2900ms).empty());
  EXPECT_EQ(arbiter.holder(), kA) << "still held at 2.9 s of silence";
  EXPECT_TRUE(arbiter.tick(3000ms).empty()) << "revocation needs strictly more than the lease";
  const LockEvents events = arbiter.tick(3001ms);
  EXPECT_EQ(events, (LockEvents{releasedAll(kA, 1, LockReleaseReason::LeaseExpired), grantedAll(kB, 2)}));
  EXPECT_EQ(arbiter.leaseDeadline(), 3001ms + kLockLease) << "the new holder's lease starts at its grant";
}

TEST(LockArbiter, RenewAndAcceptedDragsKeepTheLeaseAlive) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  EXPECT_TRUE(arbiter.handleMessage(kA, renewMsg(1), 2500ms).empty());
  EXPECT_TRUE(arbiter.tick(5000ms).empty());
  EXPECT_EQ(arbiter.acceptDrag(kA, 1, 5400ms), DragVerdict::Accepted);
  EXPECT_TRUE(arbiter.tick(8300ms).empty());
  EXPECT_EQ(arbiter.tick(8401ms).size(), 1u);
  EXPECT_EQ(arbiter.holder(), kNoPeer);
}

TEST(LockArbiter, RenewFromNonHolderOrWithWrongEpochIsIgnored) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  EXPECT_TRUE(arbiter.handleMessage(kB, renewMsg(1), 2000ms).empty());
  EXPECT_TRUE(arbiter.handleMessage(kA, renewMsg(7), 2000ms).empty());
  EXPECT_EQ(arbiter.ignoredMessages(), 2u);
  EXPECT_EQ(arbiter.tick(3001ms).size(), 1u) << "ignored renews did not extend the lease";
}

TEST(LockArbiter, HolderDisconnectFreesTheLockAtOnce) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kB, requestMsg(), 0ms);
  const LockEvents events = arbiter.peerDisconnected(kA, 10ms);
  EXPECT_EQ(events, (LockEvents{releasedAll(kA, 1, LockReleaseReason::Disconnected), grantedAll(kB, 2)}));
}

TEST(LockArbiter, QueuedPeerThatDisconnectsIsRemoved) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kB, requestMsg(), 0ms);
  arbiter.handleMessage(kC, requestMsg(), 0ms);
  EXPECT_TRUE(arbiter.peerDisconnected(kB, 5ms).empty());
  EXPECT_EQ(arbiter.queue(), std::deque<PeerId>{kC});
  EXPECT_EQ(arbiter.handleMessage(kA, releaseMsg(1), 6ms).back(), grantedAll(kC, 2)) << "B never gets the lock";
}

TEST(LockArbiter, QueuedPeerCancelsWithReleaseOfNoEpoch) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kB, requestMsg(), 0ms);
  const LockEvent dequeued{LockAudience::OnePeer, kB, {LockNoticeKind::Dequeued, kB}};
  EXPECT_EQ(arbiter.handleMessage(kB, releaseMsg(kNoEpoch), 1ms), LockEvents{dequeued});
  EXPECT_TRUE(arbiter.queue().empty());
  EXPECT_TRUE(arbiter.handleMessage(kB, releaseMsg(kNoEpoch), 2ms).empty());
  EXPECT_EQ(arbiter.ignoredMessages(), 1u);
}

TEST(LockArbiter, StaleReleaseIsIgnored) {
  LockArbiter arbiter;
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  arbiter.handleMessage(kA, releaseMsg(1), 1ms);
  arbiter.handleMessage(kA, requestMsg(), 2ms);
  EXPECT_TRUE(arbiter.handleMessage(kA, releaseMsg(1), 3ms).empty()) << "epoch 1 is over; A holds epoch 2";
  EXPECT_EQ(arbiter.holder(), kA);
  EXPECT_TRUE(arbiter.handleMessage(kB, releaseMsg(2), 3ms).empty()) << "B cannot release A's lock";
  EXPECT_EQ(arbiter.epoch(), 2u);
}

TEST(LockArbiter, DragsWithoutLockOrWithStaleEpochAreRejectedWithDistinctReasons) {
  LockArbiter arbiter;
  EXPECT_EQ(arbiter.acceptDrag(kA, 1, 0ms), DragVerdict::NotHolder) << "nobody holds the lock";
  arbiter.handleMessage(kA, requestMsg(), 0ms);
  EXPECT_EQ(arbiter.acceptDrag(kA, 1, 1ms), DragVerdict::Accepted);
  EXPECT_EQ(arbiter.acceptDrag(kB, 1, 1ms), DragVerdict::NotHolder) << "B copies A's epoch";
  arbiter.handleMessage(kA, releaseMsg(1), 2ms);
  arbiter.handleMessage(kA, requestMsg(), 3ms);
  EXPECT_EQ(arbiter.acceptDrag(kA, 1, 4ms), DragVerdict::StaleEpoch) << "a late drag from A's previous tenure";
  EXPECT_EQ(arbiter.acceptDrag(kA, 2, 4ms), DragVerdict::Accepted);
}

// Property: from a seeded random mix of requests, releases (right, stale and cancel), renews, disconnects, drags
// and ticks by 5 peers, at every step at most one peer holds, the holder is not queued, the queue has no
// duplicates and is empty when free, grants carry strictly increasing epochs, and only the holder's own epoch is
// accepted on drags.
class LockArbiterProperty : public ::testing::TestWithParam<unsigned> {};

void checkInvariants(const LockArbiter& arbiter, const LockEvents& events, LockEpoch& lastGrantEpoch) {
  std::size_t grants = 0;
  for (const LockEvent& event : events) {
    if (event.audience == LockAudience::AllPeers && event.notice.kind == LockNoticeKind::Granted) {
      ASSERT_GT(event.notice.epoch, lastGrantEpoch) << "epochs strictly increase";
      lastGrantEpoch = event.notice.epoch;
      ++grants;
    }
  }
  ASSERT_LE(grants, 1u) << "one step never grants twice";
  const auto& queue = arbiter.queue();
  ASSERT_EQ(std::set<PeerId>(queue.begin(), queue.end()).size(), queue.size()) << "queue has no duplicates";
  if (arbiter.holder() == kNoPeer) {
    ASSERT_TRUE(queue.empty()) << "a free lock has nobody waiting";
    ASSERT_EQ(arbiter.epoch(), kNoEpoch);
  } else {
    ASSERT_EQ(std::count(queue.begin(), queue.end(), arbiter.holder()), 0) << "holder is not also queued";
    ASSERT_EQ(arbiter.epoch(), lastGrantEpoch) << "the holder's epoch is the latest grant";
  }
}

TEST_P(LockArbiterProperty, AtMostOneHolderAndEpochsIncrease) {
  std::mt19937 rng(GetParam());
  std::uniform_int_distribution<PeerId> peerDist(1, 5);
  std::uniform_int_distribution<int> actionDist(0, 7);
  std::uniform_int_distribution<int> stepDist(0, 1500);
  LockArbiter arbiter;
  LockEpoch lastGrantEpoch = kNoEpoch;
  Millis now{0};
  int grantsSeen = 0;
  for (int step = 0; step < 5000; ++step) {
    now += Millis{stepDist(rng)};
    const PeerId peer = peerDist(rng);
    const LockEpoch current = arbiter.epoch();
    LockEvents events;
    switch (actionDist(rng)) {
      case 0:
      case 1:
        events = arbiter.handleMessage(peer, {LockRequestKind::Request, kNoEpoch}, now);
        break;
      case 2:
        events = arbiter.handleMessage(peer, {LockRequestKind::Release, current}, now);
        break;
      case 3:
        events = arbiter.handleMessage(peer, {LockRequestKind::Release, current > 1 ? current - 1 : kNoEpoch}, now);
        break;
      case 4:
        events = arbiter.handleMessage(peer, {LockRequestKind::Renew, current}, now);
        break;
      case 5:
        events = arbiter.peerDisconnected(peer, now);
        break;
      case 6: {
        const DragVerdict verdict = arbiter.acceptDrag(peer, current, now);
        ASSERT_EQ(verdict == DragVerdict::Accepted, peer == arbiter.holder()) << "step " << step;
        break;
      }
      default:
        events = arbiter.tick(now);
        break;
    }
    checkInvariants(arbiter, events, lastGrantEpoch);
    if (HasFatalFailure()) {
      FAIL() << "seed " << GetParam() << " step " << step;
    }
    grantsSeen = static_cast<int>(lastGrantEpoch);
  }
  EXPECT_GT(grantsSeen, 100) << "the run exercised many hand-overs";
}

INSTANTIATE_TEST_SUITE_P(Seeds, LockArbiterProperty, ::testing::Values(1u, 7u, 42u, 2024u, 99991u));

}  // namespace
}  // namespace sc::session
