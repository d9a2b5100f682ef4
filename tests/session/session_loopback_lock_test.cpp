// Loopback tests of the edit lock over the control channel (src/session/net/session_host.cpp, lock_arbiter.cpp,
// lock_client.cpp): two clients contending FIFO without a double grant, the lock freed when its holder's connection
// vanishes, drags and constraints refused without the lock or under a stale epoch. Real sockets on 127.0.0.1; raw
// peers (RawPeer) for what SessionClient never sends. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include <QtCore/QElapsedTimer>
#include <QtTest/QTest>

namespace sc::session {
namespace {

TEST_F(SessionLoopback, TwoClientsContendForTheLockFifoWithoutDoubleGrant) {
  auto host = startHost();
  auto a = join(*host, QStringLiteral("a"));
  auto b = join(*host, QStringLiteral("b"));
  int doubleGrants = 0;
  const auto check = [&] {
    if (a->lock()->canDrag() && b->lock()->canDrag()) ++doubleGrants;
  };
  QObject::connect(a.get(), &SessionClient::lockChanged, a.get(), check);
  QObject::connect(b.get(), &SessionClient::lockChanged, b.get(), check);

  ASSERT_TRUE(a->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return a->lock()->canDrag(); }, kWaitMs));
  ASSERT_TRUE(b->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->state() == LockState::Queued; }, kWaitMs));
  EXPECT_EQ(b->lock()->queuePosition(), 1u);
  EXPECT_EQ(host->lockHolder(), a->peerId());
  ASSERT_EQ(host->lockQueue().size(), 1u);
  EXPECT_EQ(host->lockQueue().front(), b->peerId());
  const LockEpoch first = a->lock()->heldEpoch();

  // The holder keeps it past the 3 s lease through renewals.
  QTest::qWait(3500);
  EXPECT_TRUE(a->lock()->canDrag());
  EXPECT_EQ(host->lockHolder(), a->peerId());

  ASSERT_TRUE(a->releaseLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->canDrag(); }, kWaitMs));
  EXPECT_GT(b->lock()->heldEpoch(), first);
  ASSERT_TRUE(QTest::qWaitFor([&] { return a->lock()->state() == LockState::Idle; }, kWaitMs));
  EXPECT_EQ(a->lock()->holder(), b->peerId());
  EXPECT_EQ(doubleGrants, 0);
}

TEST_F(SessionLoopback, LockIsFreedWhenTheHoldersConnectionVanishes) {
  auto host = startHost();
  auto a = join(*host, QStringLiteral("a"));
  auto b = join(*host, QStringLiteral("b"));
  ASSERT_TRUE(a->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return a->lock()->canDrag(); }, kWaitMs));
  ASSERT_TRUE(b->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->state() == LockState::Queued; }, kWaitMs));

  a.reset();  // no Leave: the socket just goes away
  QElapsedTimer clock;
  clock.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->canDrag(); }, 4000));
  EXPECT_LT(clock.elapsed(), 4000);
  EXPECT_EQ(host->lockHolder(), b->peerId());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->peers().peers.size() == 2; }, kWaitMs));

  // Same without a queue: a raw peer holding the lock disappears; the lock is free.
  {
    RawPeer raw(host->tcpPort());
    const std::optional<Welcome> welcome = raw.join(QStringLiteral("raw"));
    ASSERT_TRUE(welcome.has_value());
    ASSERT_TRUE(b->releaseLock());
    ASSERT_TRUE(QTest::qWaitFor([&] { return host->lockHolder() == kNoPeer; }, kWaitMs));
    ASSERT_NE(raw.acquireLock(welcome->peerId), kNoEpoch);
    EXPECT_EQ(host->lockHolder(), welcome->peerId);
  }
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->lockHolder() == kNoPeer; }, 4000));
}

TEST_F(SessionLoopback, DragsAndConstraintsWithoutTheLockOrWithAStaleEpochAreRejected) {
  auto host = startHost();
  RawPeer raw(host->tcpPort());
  const std::optional<Welcome> welcome = raw.join(QStringLiteral("raw"));
  ASSERT_TRUE(welcome.has_value());
  const auto [handle, anchors] = capConstraints();

  // No lock.
  raw.send(Drag{7, {lift(0.1)}});
  raw.send(Constraints{7, {handle}, anchors});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().constraintsRejected == 1; }, kWaitMs));
  EXPECT_EQ(host->counters().dragsNotHolder, 1u);
  EXPECT_EQ(host->counters().dragsAccepted, 0u);

  // Lock held under a second grant; the first grant's epoch is stale.
  const LockEpoch first = raw.acquireLock(welcome->peerId);
  ASSERT_NE(first, kNoEpoch);
  raw.send(LockMessage{LockRequestKind::Release, first});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->lockHolder() == kNoPeer; }, kWaitMs));
  const LockEpoch second = raw.acquireLock(welcome->peerId);
  ASSERT_GT(second, first);
  raw.send(Drag{first, {lift(0.1)}});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().dragsStale == 1; }, kWaitMs));

  // Vertex ids out of range: rejected; valid ones accepted; then a drag with the right epoch makes a frame.
  raw.send(Constraints{second, {{n() + 5}}, {}});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().constraintsRejected == 2; }, kWaitMs));
  raw.send(Constraints{second, {handle}, anchors});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().constraintsAccepted == 1; }, kWaitMs));
  const std::uint32_t before = host->currentFrame();
  raw.send(Drag{second, {lift(0.1)}});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().dragsAccepted == 1; }, kWaitMs));
  // The constraints are factored on the solver thread; a pose that arrives first waits for the install (or for the
  // coalescing timer), so its frame follows the acceptance asynchronously.
  EXPECT_TRUE(QTest::qWaitFor([&] { return host->currentFrame() > before; }, kWaitMs));
  EXPECT_GT(host->coefficients().norm(), 0.0);

  // A message a client must never send ends the connection and is counted.
  raw.send(Welcome{*welcome});
  EXPECT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().protocolErrors, 1u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 1; }, kWaitMs));
}

}  // namespace
}  // namespace sc::session
