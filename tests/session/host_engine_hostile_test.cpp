// Tests for src/session/engine/host_engine_limits.cpp and the hostile-member rules of HostEngine (docs/security.md,
// "Hostile member"): the send budget and stall deadline, per-peer rates, Constraints bounds, seats counted after the
// proof, pending slots, wrong-password waits, the lock's maximum hold while others wait, display names. Fake clock,
// no sockets.
#include "host_engine_fixture.h"
#include "session/engine/constraint_work.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace sc::session::testing {
namespace {

using HostEngineHostile = HostEngineTest;

/// The peer ids closed (ClosePeer) in `actions`.
std::vector<PeerId> closed(const HostActions& actions) {
  std::vector<PeerId> ids;
  for (const ClosePeer& close : actionsOf<ClosePeer>(actions)) ids.push_back(close.peer);
  return ids;
}

/// A report of `queued` bytes last drained at `drained`.
SendQueueReport queue(std::int64_t queued, Micros drained) { return {queued, queued, drained, false}; }

TEST_F(HostEngineHostile, PeerOverTheSendBudgetIsAbortedAndItsLockFreed) {
  HostEngineOptions options;
  options.sendBudgetBytes = 1000;
  startEngine(options);
  const PeerId hog = join(QStringLiteral("hog"));
  const PeerId honest = join(QStringLiteral("honest"));
  engine().onMessage(hog, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  ASSERT_EQ(engine().arbiter().holder(), hog);
  EXPECT_TRUE(closed(engine().onSendQueue(honest, queue(1000, now()), now())).empty()) << "at the budget: kept";
  const HostActions over = engine().onSendQueue(hog, queue(1001, now()), now());
  ASSERT_EQ(closed(over), std::vector<PeerId>{hog});
  EXPECT_EQ(actionsOf<ClosePeer>(over).front().how, ClosePeer::How::Abort);
  EXPECT_EQ(engine().counters().slowPeersDropped, 1u);
  EXPECT_EQ(engine().counters().peakSendQueueBytes, 1001);
  engine().onClosed(hog, now());
  EXPECT_EQ(engine().arbiter().holder(), kNoPeer);
  SendQueueReport refused = queue(10, now());
  refused.overBudget = true;  // the adapter refused a write: the stream is incomplete
  EXPECT_EQ(closed(engine().onSendQueue(honest, refused, now())), std::vector<PeerId>{honest});
}

TEST_F(HostEngineHostile, PeerWhoseQueueDoesNotDrainIsAbortedAfterTheStallTimeout) {
  HostEngineOptions options;
  options.sendStallTimeout = 2s;
  startEngine(options);
  const PeerId reader = join(QStringLiteral("reader"));
  const PeerId stuck = join(QStringLiteral("stuck"));
  const Micros since = now();
  advance(2s);
  EXPECT_TRUE(closed(engine().onSendQueue(stuck, queue(500, since), now())).empty()) << "exactly the timeout: kept";
  EXPECT_TRUE(closed(engine().onSendQueue(reader, queue(0, since), now())).empty()) << "an empty queue never stalls";
  advance(1ms);
  EXPECT_TRUE(closed(engine().onSendQueue(reader, queue(500, now() - 1ms), now())).empty()) << "it drains";
  EXPECT_EQ(closed(engine().onSendQueue(stuck, queue(500, since), now())), std::vector<PeerId>{stuck});
  EXPECT_EQ(engine().counters().slowPeersDropped, 1u);
}

TEST_F(HostEngineHostile, RepeatedLockAndResolutionRequestsAreThrottled) {
  startEngine();
  const PeerId member = join(QStringLiteral("member"));
  holdLockWithCap();  // the member's requests queue it and each one repeats its Queued notice
  const auto burstLock = static_cast<std::size_t>(engine().options().lockRequestRate.burst);
  const auto burstLevel = static_cast<std::size_t>(engine().options().resolutionRequestRate.burst);
  std::size_t notices = 0;
  std::size_t transfers = 0;
  for (int i = 0; i < 100; ++i) {
    notices +=
        sentTo<LockNotice>(engine().onMessage(member, LockMessage{LockRequestKind::Request, kNoEpoch}, now()), member)
            .size();
    transfers += actionsOf<StartTransfer>(engine().onMessage(member, ResolutionRequest{0}, now())).size() +
                 actionsOf<RequestLevel>(engine().onMessage(member, ResolutionRequest{0}, now())).size();
  }
  EXPECT_EQ(notices, burstLock) << "one notice per request within the burst, none after";
  EXPECT_LE(transfers, burstLevel);
  EXPECT_EQ(engine().counters().requestsThrottled, 300u - burstLock - burstLevel);
  advance(1s);  // the rate refills
  EXPECT_EQ(
      sentTo<LockNotice>(engine().onMessage(member, LockMessage{LockRequestKind::Request, kNoEpoch}, now()), member)
          .size(),
      1u);
  EXPECT_TRUE(engine().arbiter().queue().size() == 1 && engine().arbiter().queue().front() == member);
}

TEST_F(HostEngineHostile, AFloodOfMessagesClosesThePeer) {
  HostEngineOptions options;
  options.messageRate = RateLimit{100.0, 200.0};
  startEngine(options);
  const PeerId flooder = join(QStringLiteral("flooder"));
  std::vector<PeerId> closedIds;
  int sent = 0;
  for (; sent < 1000 && closedIds.empty(); ++sent) closedIds = closed(engine().onMessage(flooder, Heartbeat{}, now()));
  EXPECT_EQ(sent, 201) << "the burst, then the first message over it";
  EXPECT_EQ(closedIds, std::vector<PeerId>{flooder});
  EXPECT_EQ(engine().counters().floodingPeersDropped, 1u);
  const PeerId steady = join(QStringLiteral("steady"));
  for (int i = 0; i < 1000; ++i) {  // 10 s at 100 messages a second: within the rate
    ASSERT_TRUE(closed(engine().onMessage(steady, Heartbeat{}, now())).empty()) << i;
    advance(10ms);
  }
}

class HostEngineConstraints : public HostEngineTest {
 protected:
  /// A member holding the lock; returns its epoch.
  LockEpoch memberHoldsTheLock() {
    m_member = join(QStringLiteral("member"));
    engine().onMessage(m_member, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
    EXPECT_EQ(engine().arbiter().holder(), m_member);
    return engine().arbiter().epoch();
  }
  /// Sends Constraints{epoch, groups, anchors} from the member; true when accepted.
  bool send(LockEpoch epoch, std::vector<std::vector<std::uint32_t>> groups, std::vector<std::uint32_t> anchors) {
    const std::uint64_t before = engine().counters().constraintsAccepted;
    engine().onMessage(m_member, Constraints{epoch, std::move(groups), std::move(anchors)}, now());
    return engine().counters().constraintsAccepted == before + 1;
  }
  PeerId m_member = kNoPeer;
};

TEST_F(HostEngineConstraints, DuplicateIdsIdsOutOfRangeAndTooMuchWorkAreRejected) {
  HostEngineOptions options;
  options.constraintsRate = RateLimit{};  // this test is about the bounds
  const double m = static_cast<double>(s_model->rowCount());
  options.maxConstraintWork = 10.0 * m * m;  // 10 ids at most
  startEngine(options);
  const LockEpoch epoch = memberHoldsTheLock();
  const auto n = static_cast<std::uint32_t>(s_model->vertexCount());
  EXPECT_TRUE(send(epoch, {{1, 2, 3}}, {10, 11, 12}));
  EXPECT_FALSE(send(epoch, {{1, 2, 2}}, {10})) << "a duplicate in a group";
  EXPECT_FALSE(send(epoch, {{1, 2}, {2, 3}}, {10})) << "one vertex in two groups";
  EXPECT_FALSE(send(epoch, {{1, 2}}, {2})) << "a handle vertex anchored";
  EXPECT_FALSE(send(epoch, {{1}}, {n})) << "an id ≥ n";
  EXPECT_FALSE(send(epoch, {{1}, {}}, {})) << "an empty group";
  EXPECT_TRUE(send(epoch, {{0, 1, 2, 3, 4}}, {5, 6, 7, 8, 9})) << "10 ids: at the work bound";
  EXPECT_FALSE(send(epoch, {{0, 1, 2, 3, 4}}, {5, 6, 7, 8, 9, 10})) << "11 ids: over it";
  EXPECT_EQ(engine().counters().constraintsRejected, 6u);
}

TEST_F(HostEngineConstraints, AnchorsThinnedByTheClientsRuleFitTheWorkBound) {
  HostEngineOptions options;
  options.constraintsRate = RateLimit{};
  const int m = s_model->rowCount();
  options.maxConstraintWork = 12.0 * m * m;  // 12 ids at most
  startEngine(options);
  const LockEpoch epoch = memberHoldsTheLock();
  const std::vector<std::uint32_t> handle{1, 2, 3};
  std::vector<std::uint32_t> anchors(40);
  std::iota(anchors.begin(), anchors.end(), 10u);
  EXPECT_FALSE(send(epoch, {handle}, anchors)) << "43 ids: a dense selection over the bound";
  EXPECT_EQ(thinAnchors(anchors, handle.size(), maxConstraintIds(m, options.maxConstraintWork)), 5u);
  EXPECT_EQ(anchors, (std::vector<std::uint32_t>{10, 15, 20, 25, 30, 35, 40, 45}));
  EXPECT_TRUE(send(epoch, {handle}, anchors)) << "3 + 8 ids";
}

TEST_F(HostEngineConstraints, ConstraintsAreRateLimitedAndTheLatestIsServedLater) {
  HostEngineOptions options;
  options.constraintsRate = RateLimit{4.0, 4.0};
  startEngine(options);
  const LockEpoch epoch = memberHoldsTheLock();
  int accepted = 0;
  for (std::uint32_t i = 0; i < 100; ++i) accepted += send(epoch, {{1, 2, 3}}, {10 + i}) ? 1 : 0;
  EXPECT_EQ(accepted, 4) << "the burst; each accepted one is factored (O(ids·m² + m³))";
  EXPECT_EQ(engine().counters().requestsThrottled, 96u);
  completeConstraints(tickFor(300ms));  // a housekeeping tick once the rate allows one more
  EXPECT_EQ(engine().counters().constraintsAccepted, 5u);
  EXPECT_EQ(engine().deformer().constraints().anchors, std::vector<int>{109}) << "the latest one, not a lost one";
  completeConstraints(tickFor(2s));
  EXPECT_EQ(engine().counters().constraintsAccepted, 5u) << "served once";
}

TEST_F(HostEngineConstraints, AMembersConstraintsAreFactoredOffTheNetworkThreadAndItsDragsWait) {
  startEngine();
  const LockEpoch epoch = memberHoldsTheLock();
  const int factored = engine().deformer().factorizationCount();
  const std::vector<std::uint32_t> handle{1, 2, 3};
  const HostActions accepted = engine().onMessage(m_member, Constraints{epoch, {handle}, {10, 11, 12}}, now());
  ASSERT_EQ(actionsOf<PrepareConstraints>(accepted).size(), 1u);
  EXPECT_EQ(engine().deformer().factorizationCount(), factored) << "nothing factored on the network thread";
  EXPECT_TRUE(engine().constraintsInFlight());
  spectral::HandleTransform pose;
  pose.translation = Eigen::Vector3d(0.0, 0.0, 0.1);
  EXPECT_TRUE(actionsOf<SendFrame>(engine().onMessage(m_member, Drag{epoch, {toWire(0, pose)}}, now())).empty())
      << "the drag waits for its constraints";
  const HostActions installed = completeConstraints(accepted);
  EXPECT_EQ(engine().deformer().factorizationCount(), factored + 1);
  ASSERT_EQ(actionsOf<SendFrame>(installed).size(), 1u) << "the waiting pose, solved with the new constraints";
  EXPECT_GT(actionsOf<SendFrame>(installed).front().Z->norm(), 0.0);
  EXPECT_FALSE(engine().constraintsInFlight());
}

TEST_F(HostEngineConstraints, StaleOrOrphanedFactorisationsAreNotInstalled) {
  startEngine();
  const LockEpoch epoch = memberHoldsTheLock();
  const int factored = engine().deformer().factorizationCount();
  const HostActions first = engine().onMessage(m_member, Constraints{epoch, {{1, 2}}, {10}}, now());
  const HostActions second = engine().onMessage(m_member, Constraints{epoch, {{3, 4}}, {11}}, now());
  completeConstraints(first);
  EXPECT_EQ(engine().deformer().factorizationCount(), factored) << "superseded by the second";
  completeConstraints(second);
  EXPECT_EQ(engine().deformer().factorizationCount(), factored + 1);
  const HostActions orphan = engine().onMessage(m_member, Constraints{epoch, {{5, 6}}, {12}}, now());
  const HostActions released = engine().onMessage(m_member, LockMessage{LockRequestKind::Release, epoch}, now());
  completeConstraints(orphan);
  EXPECT_EQ(engine().deformer().factorizationCount(), factored + 1) << "the lock changed hands meanwhile";
  ASSERT_TRUE(engine().constraintsInFlight()) << "the union without the member's set is on its way";
  completeConstraints(released);
  EXPECT_EQ(engine().deformer().factorizationCount(), factored + 2);
  EXPECT_TRUE(engine().deformer().constraints().handles.empty()) << "a lease's end takes its set out";
  EXPECT_FALSE(engine().constraintsInFlight());
}

TEST_F(HostEngineHostile, SeatsAreCountedAfterTheProofNotAtAccept) {
  HostEngineOptions options;
  options.maxPeers = 2;
  startEngine(options);
  for (int i = 0; i < 5; ++i) {
    ASSERT_NE(engine().onConnectionAttempt("10.0.1." + std::to_string(i), now()).peer, kNoPeer);
  }
  EXPECT_FALSE(engine().sessionFull()) << "five pending connections take no seat";
  join(QStringLiteral("a"));
  EXPECT_FALSE(engine().sessionFull());
  join(QStringLiteral("b"));
  EXPECT_TRUE(engine().sessionFull()) << "two members: full";
}

TEST_F(HostEngineHostile, FullPendingSlotsMakeRoomForAnAddressWithFewer) {
  HostEngineOptions options;
  options.maxPendingHandshakes = 4;
  options.maxPendingPerAddress = 3;
  startEngine(options);
  std::vector<PeerId> fromA;
  for (int i = 0; i < 3; ++i) {
    fromA.push_back(engine().onConnectionAttempt("10.0.0.1", now()).peer);
    advance(1ms);
  }
  ASSERT_NE(engine().onConnectionAttempt("10.0.0.2", now()).peer, kNoPeer);
  const Admission newcomer = engine().onConnectionAttempt("10.0.0.3", now());
  EXPECT_NE(newcomer.peer, kNoPeer);
  EXPECT_EQ(newcomer.evict, fromA.front()) << "the oldest of the most represented address";
  engine().onClosed(newcomer.evict, now());
  const Admission again = engine().onConnectionAttempt("10.0.0.2", now());
  EXPECT_EQ(again.peer, kNoPeer) << "10.0.0.1 has 2, 10.0.0.2 would have 2: no eviction";
  EXPECT_EQ(again.evict, kNoPeer);
  EXPECT_EQ(engine().counters().pendingEvicted, 1u);
  EXPECT_EQ(engine().counters().connectionsOverLimit, 1u);
}

TEST_F(HostEngineHostile, WrongPasswordsAreLoggedAndMakeTheAddressWait) {
  HostEngineOptions options;
  options.freeWrongPasswords = 2;
  options.wrongPasswordBackoff = 1000ms;
  options.maxWrongPasswordBackoff = 3000ms;
  startEngine(options);
  const auto guess = [this] {
    const PeerId id = engine().onConnectionAttempt("10.0.0.66", now()).peer;
    if (id == kNoPeer) return false;
    const HostActions refused = engine().onRefused(id, RefuseReason::WrongPassword, now());
    const std::vector<LogLine> lines = actionsOf<LogLine>(refused);
    EXPECT_TRUE(lines.size() == 1 && lines.front().text.contains(QStringLiteral("10.0.0.66"))) << "logged";
    engine().onClosed(id, now());
    return true;
  };
  EXPECT_TRUE(guess());
  EXPECT_TRUE(guess());
  EXPECT_TRUE(guess()) << "the third is admitted, then the address waits 1 s";
  EXPECT_FALSE(guess());
  EXPECT_NE(engine().onConnectionAttempt("10.0.0.7", now()).peer, kNoPeer) << "other addresses are not affected";
  advance(1001ms);
  EXPECT_TRUE(guess()) << "then 2 s";
  advance(1999ms);
  EXPECT_FALSE(guess());
  advance(2ms);
  EXPECT_TRUE(guess()) << "then 3 s (the cap)";
  advance(3001ms);
  EXPECT_TRUE(guess());
  EXPECT_EQ(engine().counters().wrongPasswords, 6u);
  EXPECT_EQ(engine().counters().connectionsThrottled, 2u);
}

TEST_F(HostEngineHostile, ALockHolderIsRevokedAfterTheMaximumHoldWhileOthersWait) {
  HostEngineOptions options;
  options.maxLockHoldWhileWaited = 5000ms;
  startEngine(options);
  const PeerId holder = join(QStringLiteral("holder"));
  const PeerId waiter = join(QStringLiteral("waiter"));
  engine().onMessage(holder, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  const LockEpoch epoch = engine().arbiter().epoch();
  const auto renewFor = [&](Micros duration) {
    for (const Micros end = now() + duration; now() < end;) {
      engine().onHeard(holder, now());  // both keep talking (heartbeats): neither is silent
      engine().onHeard(waiter, now());
      engine().onMessage(holder, LockMessage{LockRequestKind::Renew, epoch}, now());
      tickFor(500ms);
    }
  };
  renewFor(20s);
  EXPECT_EQ(engine().arbiter().holder(), holder) << "nobody waits: renewing keeps the lock";
  engine().onMessage(waiter, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  renewFor(4500ms);
  EXPECT_EQ(engine().arbiter().holder(), holder);
  renewFor(1000ms);
  EXPECT_EQ(engine().arbiter().holder(), waiter) << "5 s after the waiter came: handed over";
  EXPECT_EQ(engine().counters().locksRevokedForWaiters, 1u);
}

TEST(HostDisplayNames, InvisibleAndControlCharactersAreRefused) {
  for (const char16_t* bad : {u"a\u200Bb", u"\u202Eevil", u"\u3164", u"x\u2060", u"na\uFEFFme", u"\uE000", u"a\tb"}) {
    EXPECT_FALSE(isAcceptableDisplayName(QString::fromUtf16(bad))) << QString::fromUtf16(bad).toStdString();
  }
  for (const char16_t* good : {u"Zoë", u"Ana María", u"李雷", u"O'Brien"}) {
    EXPECT_TRUE(isAcceptableDisplayName(QString::fromUtf16(good))) << QString::fromUtf16(good).toStdString();
  }
}

}  // namespace
}  // namespace sc::session::testing
