// Tests for src/session/engine/host_engine_moderation.cpp (and the Leave reasons of shutdown()): the host's user
// removes a member, takes the lock back, and everybody learns who waits for the lock; fake clock, no sockets.
#include "host_engine_fixture.h"

namespace sc::session::testing {
namespace {

using HostEngineModeration = HostEngineTest;

LockMessage lockRequest() { return {LockRequestKind::Request, kNoEpoch}; }

TEST_F(HostEngineModeration, ShutdownTellsEveryMemberThatTheHostEndedTheSession) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  const HostActions actions = engine().shutdown(now());
  for (const PeerId peer : {alice, bob}) {
    const std::vector<Leave> leaves = sentTo<Leave>(actions, peer);
    ASSERT_EQ(leaves.size(), 1u);
    EXPECT_EQ(leaves[0].reason, LeaveReason::HostEnded);
  }
  EXPECT_EQ(actionsOf<ClosePeer>(actions).size(), 2u);
}

TEST_F(HostEngineModeration, KickSendsLeaveKickedClosesThePeerAndFreesItsLock) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  engine().onMessage(alice, lockRequest(), now());
  engine().onMessage(bob, lockRequest(), now());
  ASSERT_EQ(engine().arbiter().holder(), alice);

  bool kicked = false;
  const HostActions actions = engine().kick(alice, now(), QStringLiteral("too many drags"), &kicked);
  EXPECT_TRUE(kicked);
  const std::vector<Leave> leaves = sentTo<Leave>(actions, alice);
  ASSERT_EQ(leaves.size(), 1u);
  EXPECT_EQ(leaves[0], (Leave{LeaveReason::Kicked, QStringLiteral("too many drags")}));
  const std::vector<ClosePeer> closes = actionsOf<ClosePeer>(actions);
  ASSERT_EQ(closes.size(), 1u);
  EXPECT_EQ(closes[0].peer, alice);
  EXPECT_EQ(closes[0].how, ClosePeer::How::Graceful) << "the Leave is written first";
  EXPECT_EQ(engine().arbiter().holder(), bob) << "the lock goes at once, as on a disconnect";
  const std::vector<LockNotice> notices = sentToAll<LockNotice>(actions);
  ASSERT_FALSE(notices.empty());
  EXPECT_EQ(notices[0].kind, LockNoticeKind::Released);
  EXPECT_EQ(notices[0].reason, LockReleaseReason::Disconnected);
  const std::vector<PeerList> lists = sentToAll<PeerList>(actions);
  ASSERT_EQ(lists.size(), 1u);
  EXPECT_EQ(lists[0].peers.size(), 2u) << "the host and bob";
  EXPECT_EQ(engine().peerList().peers.size(), 2u);
  EXPECT_TRUE(engine().onMessage(alice, lockRequest(), now()).list.empty()) << "a kicked peer is no longer heard";

  engine().kick(alice, now(), {}, &kicked);
  EXPECT_FALSE(kicked) << "already closing";
  engine().kick(kHostPeer, now(), {}, &kicked);
  EXPECT_FALSE(kicked) << "the host cannot remove itself";
  engine().kick(999, now(), {}, &kicked);
  EXPECT_FALSE(kicked) << "no such peer";
  engine().onClosed(alice, now());
  EXPECT_EQ(engine().arbiter().holder(), bob) << "the close itself changes nothing more";
}

TEST_F(HostEngineModeration, ForceReleaseRevokesTheHolderAndGrantsTheNext) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  bool revoked = true;
  EXPECT_TRUE(actionsOf<LockChanged>(engine().forceReleaseLock(now(), &revoked)).empty());
  EXPECT_FALSE(revoked) << "nobody holds the lock";
  engine().onMessage(alice, lockRequest(), now());
  engine().onMessage(bob, lockRequest(), now());

  const HostActions actions = engine().forceReleaseLock(now(), &revoked);
  EXPECT_TRUE(revoked);
  const std::vector<LockNotice> notices = sentToAll<LockNotice>(actions);
  ASSERT_GE(notices.size(), 2u);
  EXPECT_EQ(notices[0], (LockNotice{LockNoticeKind::Released, alice, 1, 0, LockReleaseReason::RevokedByHost, {}}));
  EXPECT_EQ(notices[1].kind, LockNoticeKind::Granted);
  EXPECT_EQ(notices[1].peer, bob);
  EXPECT_EQ(engine().arbiter().holder(), bob);
  Drag drag;
  drag.epoch = 1;
  engine().onMessage(alice, drag, now());
  EXPECT_EQ(engine().counters().dragsNotHolder, 1u) << "the revoked holder's drags are refused";

  // The host's own user can take the lock from a member for itself: revoke, then request.
  engine().forceReleaseLock(now(), &revoked);
  bool sent = false;
  engine().requestLock(now(), &sent);
  EXPECT_TRUE(sent);
  EXPECT_EQ(engine().arbiter().holder(), kHostPeer);
}

TEST_F(HostEngineModeration, EverybodyLearnsWhoWaitsForTheLock) {
  startEngine();
  bool sent = false;
  engine().requestLock(now(), &sent);  // the host's own user holds the lock
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));

  HostActions actions = engine().onMessage(alice, lockRequest(), now());
  std::vector<LockNotice> waiting = sentToAll<LockNotice>(actions);
  ASSERT_EQ(waiting.size(), 1u);
  EXPECT_EQ(waiting[0].kind, LockNoticeKind::Waiting);
  EXPECT_EQ(waiting[0].waiting, std::vector<PeerId>{alice});
  EXPECT_EQ(engine().localLock().waiting(), std::vector<PeerId>{alice}) << "the holder (the host's user) knows";
  EXPECT_EQ(actionsOf<LockChanged>(actions).size(), 1u) << "the window redraws its lock line";

  actions = engine().onMessage(bob, lockRequest(), now());
  EXPECT_EQ(sentToAll<LockNotice>(actions).at(0).waiting, (std::vector<PeerId>{alice, bob}));
  EXPECT_TRUE(sentToAll<LockNotice>(engine().onMessage(bob, lockRequest(), now())).empty())
      << "a repeated request changes no queue: nothing announced";

  const PeerId carol = join(QStringLiteral("carol"));
  const std::vector<LockNotice> toCarol = sentTo<LockNotice>(m_actions, carol);
  ASSERT_EQ(toCarol.size(), 2u) << "the grant and the queue";
  EXPECT_EQ(toCarol[1].waiting, (std::vector<PeerId>{alice, bob}));

  actions = engine().onMessage(alice, LockMessage{LockRequestKind::Release, kNoEpoch}, now());  // alice gives up
  EXPECT_EQ(sentToAll<LockNotice>(actions).at(0).waiting, std::vector<PeerId>{bob});
  actions = engine().onClosed(bob, now());
  const std::vector<LockNotice> empty = sentToAll<LockNotice>(actions);
  ASSERT_EQ(empty.size(), 1u);
  EXPECT_EQ(empty[0].kind, LockNoticeKind::Waiting);
  EXPECT_TRUE(empty[0].waiting.empty()) << "nobody waits any more";
  EXPECT_TRUE(engine().localLock().waiting().empty());
}

}  // namespace
}  // namespace sc::session::testing
