// Tests for src/session/engine/lock_client.cpp: the peer's edit-lock state machine, alone and wired to a LockArbiter
// through an in-memory loop (no sockets).
#include "session/engine/lock_client.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

#include "session/engine/lock_arbiter.h"

namespace sc::session {
namespace {

using namespace std::chrono_literals;

constexpr PeerId kSelf = 1;
constexpr PeerId kOther = 2;

LockNotice granted(PeerId peer, LockEpoch epoch) { return {LockNoticeKind::Granted, peer, epoch}; }
LockNotice released(PeerId peer, LockEpoch epoch, LockReleaseReason reason) {
  return {LockNoticeKind::Released, peer, epoch, 0, reason};
}
LockNotice queued(PeerId peer, std::uint32_t position) { return {LockNoticeKind::Queued, peer, kNoEpoch, position}; }

TEST(LockClient, RequestThenGrantGivesHeld) {
  LockClient client(kSelf);
  EXPECT_EQ(client.state(), LockState::Idle);
  EXPECT_EQ(client.request(0ms), (LockMessage{LockRequestKind::Request, kNoEpoch}));
  EXPECT_EQ(client.state(), LockState::Requested);
  EXPECT_EQ(client.request(1ms), std::nullopt) << "asking twice sends nothing";
  EXPECT_FALSE(client.canDrag());
  EXPECT_EQ(client.apply(granted(kSelf, 4), 2ms), std::nullopt);
  EXPECT_EQ(client.state(), LockState::Held);
  EXPECT_TRUE(client.canDrag());
  EXPECT_EQ(client.heldEpoch(), 4u);
  EXPECT_EQ(client.holder(), kSelf);
}

TEST(LockClient, QueuedThenGrantedWhenHolderReleases) {
  LockClient client(kSelf);
  client.apply(granted(kOther, 1), 0ms);
  EXPECT_EQ(client.holder(), kOther) << "every peer sees who holds the lock";
  client.request(1ms);
  client.apply(queued(kSelf, 1), 2ms);
  EXPECT_EQ(client.state(), LockState::Queued);
  EXPECT_EQ(client.queuePosition(), 1u);
  client.apply(released(kOther, 1, LockReleaseReason::Released), 3ms);
  EXPECT_EQ(client.holder(), kNoPeer);
  client.apply(granted(kSelf, 2), 3ms);
  EXPECT_EQ(client.state(), LockState::Held);
  EXPECT_EQ(client.queuePosition(), 0u);
  EXPECT_EQ(client.heldEpoch(), 2u);
}

TEST(LockClient, RevokedHolderReturnsToIdleAndKnowsWhy) {
  LockClient client(kSelf);
  client.request(0ms);
  client.apply(granted(kSelf, 1), 0ms);
  client.apply(released(kSelf, 1, LockReleaseReason::LeaseExpired), 3100ms);
  EXPECT_EQ(client.state(), LockState::Idle);
  EXPECT_FALSE(client.canDrag());
  EXPECT_EQ(client.heldEpoch(), kNoEpoch);
  EXPECT_EQ(client.lastLoss(), LockReleaseReason::LeaseExpired);
}

TEST(LockClient, KnowsWhoWaitsAndFollowsItsPlaceInTheQueue) {
  LockClient holder(kSelf);
  holder.request(0ms);
  holder.apply(granted(kSelf, 1), 1ms);
  EXPECT_TRUE(holder.waiting().empty());
  holder.apply({LockNoticeKind::Waiting, kNoPeer, kNoEpoch, 0, {}, {kOther, 7}}, 2ms);
  EXPECT_EQ(holder.waiting(), (std::vector<PeerId>{kOther, 7}));
  EXPECT_EQ(holder.state(), LockState::Held) << "a queue notice changes no state";
  EXPECT_EQ(holder.ignoredNotices(), 0u);

  LockClient waiter(7);
  waiter.request(0ms);
  waiter.apply(queued(7, 2), 1ms);
  waiter.apply({LockNoticeKind::Waiting, kNoPeer, kNoEpoch, 0, {}, {7}}, 2ms);  // kOther gave up its place
  EXPECT_EQ(waiter.queuePosition(), 1u);
  EXPECT_EQ(waiter.state(), LockState::Queued);
}

TEST(LockClient, RevokedByTheHostKnowsWhy) {
  LockClient client(kSelf);
  client.request(0ms);
  client.apply(granted(kSelf, 3), 1ms);
  client.apply(released(kSelf, 3, LockReleaseReason::RevokedByHost), 2ms);
  EXPECT_EQ(client.state(), LockState::Idle);
  EXPECT_EQ(client.lastLoss(), LockReleaseReason::RevokedByHost);
  EXPECT_FALSE(client.canDrag());
  client.request(3ms);
  EXPECT_FALSE(client.lastLoss().has_value()) << "a new request forgets it";
}

TEST(LockClient, ReleaseGoesThroughReleasing) {
  LockClient client(kSelf);
  client.request(0ms);
  client.apply(granted(kSelf, 3), 0ms);
  EXPECT_EQ(client.release(10ms), (LockMessage{LockRequestKind::Release, 3}));
  EXPECT_EQ(client.state(), LockState::Releasing);
  EXPECT_FALSE(client.canDrag()) << "no drags once the release is sent";
  EXPECT_EQ(client.release(11ms), std::nullopt);
  client.apply(released(kSelf, 3, LockReleaseReason::Released), 12ms);
  EXPECT_EQ(client.state(), LockState::Idle);
  EXPECT_EQ(client.lastLoss(), LockReleaseReason::Released);
}

TEST(LockClient, CancelWhileQueuedEndsOnDequeued) {
  LockClient client(kSelf);
  client.request(0ms);
  client.apply(queued(kSelf, 2), 0ms);
  EXPECT_EQ(client.release(5ms), (LockMessage{LockRequestKind::Release, kNoEpoch}));
  EXPECT_EQ(client.state(), LockState::Releasing);
  client.apply(granted(kSelf, 9), 6ms);
  EXPECT_EQ(client.state(), LockState::Releasing) << "a grant that crossed our cancel does not make us hold";
  client.apply(LockNotice{LockNoticeKind::Dequeued, kSelf}, 7ms);
  EXPECT_EQ(client.state(), LockState::Idle);
}

TEST(LockClient, UnwantedGrantIsHandedBack) {
  LockClient client(kSelf);
  EXPECT_EQ(client.apply(granted(kSelf, 5), 0ms), (LockMessage{LockRequestKind::Release, 5}));
  EXPECT_EQ(client.state(), LockState::Idle);
}

TEST(LockClient, AGrantToAnotherWhileHeldKeepsOursSinceSeveralMayHoldAtOnce) {
  LockClient client(kSelf);
  client.request(0ms);
  client.apply(granted(kSelf, 1), 0ms);
  client.apply(granted(kOther, 2), 5000ms);
  EXPECT_EQ(client.state(), LockState::Held);
  EXPECT_EQ(client.heldEpoch(), 1u);
  EXPECT_EQ(client.holders(), (std::vector<PeerId>{kSelf, kOther}));
  EXPECT_EQ(client.holderEpoch(), 2u);
  client.apply(LockNotice{LockNoticeKind::Released, kSelf, 1, 0, LockReleaseReason::Released}, 5001ms);
  EXPECT_EQ(client.state(), LockState::Idle);
  EXPECT_EQ(client.holders(), (std::vector<PeerId>{kOther}));
  client.apply(granted(kSelf, 1), 5002ms);
  EXPECT_EQ(client.holders(), (std::vector<PeerId>{kOther})) << "an older grant arriving late is ignored";
}

TEST(LockClient, ARefusalOfOurConstraintsIsKeptForTheUserAndChangesNoState) {
  LockClient client(kSelf);
  client.request(0ms);
  client.apply(granted(kSelf, 3), 0ms);
  LockNotice refused{LockNoticeKind::Refused, kSelf, 3, 0, LockReleaseReason::Released, {kOther}};
  client.apply(refused, 1ms);
  ASSERT_TRUE(client.lastRefusal().has_value());
  EXPECT_EQ(client.lastRefusal()->holders, (std::vector<PeerId>{kOther}));
  EXPECT_EQ(client.lastRefusal()->serial, 1u);
  EXPECT_EQ(client.state(), LockState::Held);
  refused.epoch = 2;  // a stale one, for an earlier tenure
  client.apply(refused, 2ms);
  EXPECT_EQ(client.lastRefusal()->serial, 1u);
  EXPECT_EQ(client.ignoredNotices(), 1u);
}

TEST(LockClient, RenewTiming) {
  LockClient client(kSelf, 1000ms);
  EXPECT_EQ(client.pollRenew(5000ms), std::nullopt) << "nothing to renew unless held";
  EXPECT_EQ(client.nextRenewDue(), std::nullopt);
  client.request(0ms);
  client.apply(granted(kSelf, 1), 100ms);
  EXPECT_EQ(client.nextRenewDue(), 1100ms);
  EXPECT_EQ(client.pollRenew(1099ms), std::nullopt);
  EXPECT_EQ(client.pollRenew(1100ms), (LockMessage{LockRequestKind::Renew, 1}));
  EXPECT_EQ(client.pollRenew(1500ms), std::nullopt);
  EXPECT_EQ(client.nextRenewDue(), 2100ms);
  EXPECT_EQ(client.pollRenew(2300ms), (LockMessage{LockRequestKind::Renew, 1}));
}

// An in-memory session: the arbiter's events are delivered to the addressed clients, their replies fed back.
class LockLoop {
 public:
  explicit LockLoop(std::initializer_list<PeerId> peers) {
    for (PeerId peer : peers) {
      m_clients.emplace(peer, LockClient(peer));
    }
  }
  LockClient& client(PeerId peer) { return m_clients.at(peer); }
  LockArbiter& arbiter() { return m_arbiter; }

  void send(PeerId from, const std::optional<LockMessage>& message, Millis now) {
    if (message) {
      deliver(m_arbiter.handleMessage(from, *message, now), now);
    }
  }
  void deliver(const LockEvents& events, Millis now) {
    for (const LockEvent& event : events) {
      for (auto& [peer, client] : m_clients) {
        if (event.audience == LockAudience::AllPeers || event.recipient == peer) {
          send(peer, client.apply(event.notice, now), now);
        }
      }
    }
  }
  /// Advances to @p now in 100 ms steps; peers in @p renewing poll their renew timer, the host ticks.
  void run(Millis from, Millis now, std::initializer_list<PeerId> renewing) {
    for (Millis t = from; t <= now; t += 100ms) {
      for (PeerId peer : renewing) {
        send(peer, client(peer).pollRenew(t), t);
      }
      deliver(m_arbiter.tick(t), t);
    }
  }

 private:
  LockArbiter m_arbiter;
  std::map<PeerId, LockClient> m_clients;
};

TEST(LockClientWithArbiter, RenewingHolderKeepsTheLockSilentOneLosesIt) {
  LockLoop loop({kSelf, kOther});
  loop.send(kSelf, loop.client(kSelf).request(0ms), 0ms);
  loop.send(kOther, loop.client(kOther).request(0ms), 0ms);
  EXPECT_EQ(loop.client(kOther).state(), LockState::Queued);
  loop.run(0ms, 30000ms, {kSelf});
  EXPECT_EQ(loop.client(kSelf).state(), LockState::Held) << "renews every second keep a 3 s lease";

  loop.run(30100ms, 33000ms, {});  // the holder falls silent after its renew at 30 s
  EXPECT_EQ(loop.client(kSelf).state(), LockState::Held) << "still held at 3.0 s of silence";
  loop.run(33100ms, 33100ms, {});
  EXPECT_EQ(loop.client(kSelf).state(), LockState::Idle);
  EXPECT_EQ(loop.client(kSelf).lastLoss(), LockReleaseReason::LeaseExpired);
  EXPECT_EQ(loop.client(kOther).state(), LockState::Held);
  EXPECT_EQ(loop.client(kSelf).holder(), kOther) << "the revoked peer sees the new holder";
  EXPECT_EQ(loop.arbiter().acceptDrag(kOther, loop.client(kOther).heldEpoch(), 33100ms), DragVerdict::Accepted);
}

TEST(LockClientWithArbiter, CancelRacingAGrantEndsWithTheLockFree) {
  LockLoop loop({kSelf, kOther});
  loop.send(kOther, loop.client(kOther).request(0ms), 0ms);
  loop.send(kSelf, loop.client(kSelf).request(0ms), 0ms);
  const std::optional<LockMessage> cancel = loop.client(kSelf).release(1ms);  // not yet at the host
  loop.send(kOther, loop.client(kOther).release(2ms), 2ms);                   // the host grants kSelf here
  EXPECT_EQ(loop.arbiter().holder(), kSelf);
  loop.send(kSelf, cancel, 3ms);  // the host now sees a cancel from its holder
  EXPECT_EQ(loop.arbiter().holder(), kNoPeer);
  EXPECT_EQ(loop.client(kSelf).state(), LockState::Idle);
  EXPECT_EQ(loop.client(kOther).holder(), kNoPeer);
}

// Property: 5 peers driven by a seeded random mix of request, release, silence and disconnect-and-rejoin, with
// all notices delivered in order; at every step at most one client believes it holds the lock, and it is the
// arbiter's holder with the arbiter's epoch.
class LockProtocolProperty : public ::testing::TestWithParam<unsigned> {};

TEST_P(LockProtocolProperty, AtMostOneClientHolds) {
  std::mt19937 rng(GetParam());
  std::uniform_int_distribution<PeerId> peerDist(1, 5);
  std::uniform_int_distribution<int> actionDist(0, 4);
  LockLoop loop({1, 2, 3, 4, 5});
  Millis now{0};
  int heldSteps = 0;
  for (int step = 0; step < 3000; ++step) {
    now += 100ms;
    const PeerId peer = peerDist(rng);
    LockClient& client = loop.client(peer);
    switch (actionDist(rng)) {
      case 0:
        loop.send(peer, client.request(now), now);
        break;
      case 1:
        loop.send(peer, client.release(now), now);
        break;
      case 2:
        loop.send(peer, client.pollRenew(now), now);
        break;
      case 3:
        loop.deliver(loop.arbiter().peerDisconnected(peer, now), now);
        client = LockClient(peer);  // it reconnects with a fresh state machine
        break;
      default:
        loop.deliver(loop.arbiter().tick(now), now);
        break;
    }
    int holding = 0;
    for (PeerId p = 1; p <= 5; ++p) {
      if (loop.client(p).state() == LockState::Held) {
        ++holding;
        ASSERT_EQ(loop.arbiter().holder(), p) << "seed " << GetParam() << " step " << step;
        ASSERT_EQ(loop.client(p).heldEpoch(), loop.arbiter().epoch()) << "seed " << GetParam() << " step " << step;
      }
    }
    ASSERT_LE(holding, 1) << "seed " << GetParam() << " step " << step;
    heldSteps += holding;
  }
  EXPECT_GT(heldSteps, 500) << "the run spent a fair share of steps with a holder";
}

INSTANTIATE_TEST_SUITE_P(Seeds, LockProtocolProperty, ::testing::Values(3u, 11u, 123u, 4096u, 65537u));

}  // namespace
}  // namespace sc::session
