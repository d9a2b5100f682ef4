// Tests for LockArbiter with several leases at once (issue 15, "several people drag at once"): each holder has its
// own epoch and lease, the queue waits only when every lease is taken, and a lease frees as the single lock did.
#include "session/engine/lock_arbiter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace sc::session {
namespace {

using namespace std::chrono_literals;

constexpr LockMessage kRequest{LockRequestKind::Request, kNoEpoch};

TEST(LockLeases, TwoPeersHoldAtOnceWithTheirOwnEpochsAndTheThirdWaits) {
  LockArbiter arbiter(kLockLease, Millis{0}, 2);
  arbiter.handleMessage(2, kRequest, 0ms);
  arbiter.handleMessage(3, kRequest, 1ms);
  const LockEvents queued = arbiter.handleMessage(4, kRequest, 2ms);
  ASSERT_EQ(arbiter.holders(), (std::vector<LockHolding>{{2, 1}, {3, 2}}));
  ASSERT_EQ(queued.size(), 1u);
  EXPECT_EQ(queued[0].notice.kind, LockNoticeKind::Queued);
  EXPECT_EQ(arbiter.acceptDrag(2, 1, 3ms), DragVerdict::Accepted);
  EXPECT_EQ(arbiter.acceptDrag(3, 2, 3ms), DragVerdict::Accepted);
  EXPECT_EQ(arbiter.acceptDrag(3, 1, 3ms), DragVerdict::StaleEpoch) << "3 stamps 2's epoch";
  EXPECT_EQ(arbiter.acceptDrag(4, 2, 3ms), DragVerdict::NotHolder);

  // 2 vanishes: its lease frees at once and the waiting 4 gets it, 3 keeps its own
  const LockEvents events = arbiter.peerDisconnected(2, 4ms);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].notice.kind, LockNoticeKind::Released);
  EXPECT_EQ(events[0].notice.reason, LockReleaseReason::Disconnected);
  EXPECT_EQ(events[1].notice, (LockNotice{LockNoticeKind::Granted, 4, 3}));
  EXPECT_EQ(arbiter.holders(), (std::vector<LockHolding>{{3, 2}, {4, 3}}));
  EXPECT_TRUE(arbiter.queue().empty());
}

TEST(LockLeases, EachLeaseExpiresOnItsOwnSilence) {
  LockArbiter arbiter(kLockLease, Millis{0}, 3);
  arbiter.handleMessage(2, kRequest, 0ms);
  arbiter.handleMessage(3, kRequest, 0ms);
  arbiter.handleMessage(3, {LockRequestKind::Renew, 2}, 2000ms);
  const LockEvents events = arbiter.tick(3001ms);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].notice.peer, 2u);
  EXPECT_EQ(arbiter.holders(), (std::vector<LockHolding>{{3, 2}}));
  EXPECT_EQ(arbiter.epochOf(3), 2u);
  EXPECT_EQ(arbiter.epochOf(2), kNoEpoch);
}

TEST(LockLeases, TheHostRevokesOneLeaseOrEveryLease) {
  LockArbiter arbiter(kLockLease, Millis{0}, 2);
  arbiter.handleMessage(2, kRequest, 0ms);
  arbiter.handleMessage(3, kRequest, 0ms);
  arbiter.handleMessage(4, kRequest, 0ms);
  const LockEvents one = arbiter.revokeByHost(1ms, 3);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].notice.reason, LockReleaseReason::RevokedByHost);
  EXPECT_EQ(arbiter.holders(), (std::vector<LockHolding>{{2, 1}, {4, 3}})) << "the waiting 4 takes 3's place";
  EXPECT_TRUE(arbiter.revokeByHost(2ms, 9).empty()) << "9 holds nothing";
  const LockEvents all = arbiter.revokeByHost(3ms);
  EXPECT_EQ(all.size(), 2u);
  EXPECT_TRUE(arbiter.holders().empty());
}

TEST(LockLeases, TheOldestLeaseMakesRoomAfterHoldingTooLongWhileOthersWait) {
  LockArbiter arbiter(kLockLease, Millis{5000}, 2);
  arbiter.handleMessage(2, kRequest, 0ms);
  arbiter.handleMessage(3, kRequest, 1000ms);
  arbiter.handleMessage(4, kRequest, 2000ms);
  for (Millis t = 2500ms; t <= 7000ms; t += 500ms) {
    arbiter.handleMessage(2, {LockRequestKind::Renew, 1}, t);
    arbiter.handleMessage(3, {LockRequestKind::Renew, 2}, t);
    arbiter.tick(t);
  }
  EXPECT_EQ(arbiter.holders(), (std::vector<LockHolding>{{2, 1}, {3, 2}})) << "5 s from when 4 began to wait";
  arbiter.tick(7001ms);
  EXPECT_EQ(arbiter.holders(), (std::vector<LockHolding>{{3, 2}, {4, 3}}));
  EXPECT_EQ(arbiter.revokedForWaiters(), 1u);
}

// Property: a seeded random mix of requests, releases, renews, disconnects, drags and ticks by 6 peers over 3
// leases: at every step at most 3 distinct holders, none queued, the queue without duplicates and non-empty only
// when every lease is taken, grant epochs strictly increasing, and a drag accepted exactly with its holder's epoch.
class LockLeasesProperty : public ::testing::TestWithParam<unsigned> {};

TEST_P(LockLeasesProperty, NeverMoreThanMaxHoldersAndEpochsIncrease) {
  constexpr int kLeases = 3;
  std::mt19937 rng(GetParam());
  std::uniform_int_distribution<PeerId> peerDist(1, 6);
  std::uniform_int_distribution<int> actionDist(0, 7);
  std::uniform_int_distribution<int> stepDist(0, 1500);
  LockArbiter arbiter(kLockLease, Millis{4000}, kLeases);
  LockEpoch lastGrant = kNoEpoch;
  Millis now{0};
  for (int step = 0; step < 5000; ++step) {
    now += Millis{stepDist(rng)};
    const PeerId peer = peerDist(rng);
    const LockEpoch own = arbiter.epochOf(peer);
    LockEvents events;
    switch (actionDist(rng)) {
      case 0:
      case 1:
        events = arbiter.handleMessage(peer, kRequest, now);
        break;
      case 2:
        events = arbiter.handleMessage(peer, {LockRequestKind::Release, own}, now);
        break;
      case 3:
        events = arbiter.handleMessage(peer, {LockRequestKind::Renew, own}, now);
        break;
      case 4:
        events = arbiter.peerDisconnected(peer, now);
        break;
      case 5: {
        const LockEpoch someone = arbiter.epoch();
        const DragVerdict verdict = arbiter.acceptDrag(peer, someone, now);
        ASSERT_EQ(verdict == DragVerdict::Accepted, someone != kNoEpoch && arbiter.epochOf(peer) == someone);
        break;
      }
      case 6:
        events = arbiter.revokeByHost(now, peer);
        break;
      default:
        events = arbiter.tick(now);
        break;
    }
    for (const LockEvent& event : events) {
      if (event.notice.kind == LockNoticeKind::Granted && event.audience == LockAudience::AllPeers) {
        ASSERT_GT(event.notice.epoch, lastGrant);
        lastGrant = event.notice.epoch;
      }
    }
    const std::vector<LockHolding> holders = arbiter.holders();
    std::set<PeerId> distinct;
    for (const LockHolding& h : holders) distinct.insert(h.peer);
    ASSERT_LE(holders.size(), static_cast<std::size_t>(kLeases)) << "step " << step;
    ASSERT_EQ(distinct.size(), holders.size());
    const auto& queue = arbiter.queue();
    ASSERT_EQ(std::set<PeerId>(queue.begin(), queue.end()).size(), queue.size());
    for (const PeerId waiting : queue) {
      ASSERT_EQ(distinct.count(waiting), 0u) << "a holder is not also queued";
    }
    if (!queue.empty()) {
      ASSERT_EQ(holders.size(), static_cast<std::size_t>(kLeases)) << "step " << step;
    }
  }
  EXPECT_GT(lastGrant, 100u) << "the run exercised many grants";
}

INSTANTIATE_TEST_SUITE_P(Seeds, LockLeasesProperty, ::testing::Values(3u, 11u, 2026u));

}  // namespace
}  // namespace sc::session
