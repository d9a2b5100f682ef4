// Tests for src/session/engine/host_engine_peers.cpp and host_engine_lock.cpp: what a Welcome sends, transfer
// scheduling (pick, build, transfer, Keyframe and PeerList), the fallback of a failed level, lock dispatch and the
// rules for peers' messages; with a fake clock and no sockets.
#include "host_engine_fixture.h"

#include <algorithm>

namespace sc::session::testing {
namespace {

class HostEnginePeers : public HostEngineTest {
 protected:
  /// The model's vertex count n (the full model's target).
  static std::uint32_t full() { return static_cast<std::uint32_t>(s_model->vertexCount()); }
  /// Starts an engine whose ladder is 50%, 20% and 5% of n.
  void startWithLadder() { startEngine({}, {full() / 2, full() / 5, full() / 20}); }
};

TEST_F(HostEnginePeers, WelcomeSendsPeerListLevelsAndTheCurrentGrant) {
  startWithLadder();
  bool sent = false;
  engine().requestLock(now(), &sent);
  ASSERT_TRUE(sent);
  const PeerId peer = join(QStringLiteral("alice"));
  const std::vector<PeerList> lists = sentToAll<PeerList>(m_actions);
  ASSERT_EQ(lists.size(), 1u);
  ASSERT_EQ(lists[0].peers.size(), 2u);
  EXPECT_EQ(lists[0].peers[0].peerId, kHostPeer);
  EXPECT_EQ(lists[0].peers[1].name, QStringLiteral("alice"));
  EXPECT_EQ(lists[0].peers[1].vertexCount, 0u) << "no model yet";
  const std::vector<LevelList> levels = sentTo<LevelList>(m_actions, peer);
  ASSERT_EQ(levels.size(), 1u);
  EXPECT_EQ(levels[0].total, 4u) << "full + three rungs";
  EXPECT_TRUE(levels[0].levels.empty()) << "none built yet";
  EXPECT_EQ(actionsOf<PrefetchLevels>(m_actions).size(), 1u);
  const std::vector<LockNotice> grant = sentTo<LockNotice>(m_actions, peer);
  ASSERT_EQ(grant.size(), 1u);
  EXPECT_EQ(grant[0].kind, LockNoticeKind::Granted);
  EXPECT_EQ(grant[0].peer, kHostPeer);
  EXPECT_EQ(actionsOf<PeersChanged>(m_actions).size(), 1u);
}

TEST_F(HostEnginePeers, TransferWaitsForItsLevelThenKeyframeAndPeerList) {
  startWithLadder();
  const PeerId peer = join(QStringLiteral("alice"));
  HostActions actions = engine().onMessage(peer, ResolutionRequest{full() / 2 - 1}, now());
  const std::vector<RequestLevel> requests = actionsOf<RequestLevel>(actions);
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].target, full() / 2) << "the closest rung";
  EXPECT_TRUE(actionsOf<StartTransfer>(actions).empty()) << "not built yet";

  actions = engine().onLevelReady(full() / 2, {full() / 2 - 1, 150, 5000}, now());
  const std::vector<LevelList> levels = sentToAll<LevelList>(actions);
  ASSERT_EQ(levels.size(), 1u) << "the new level's figures to everybody";
  ASSERT_EQ(levels[0].levels.size(), 1u);
  EXPECT_EQ(levels[0].levels[0].vertexCount, full() / 2 - 1);
  const std::vector<StartTransfer> transfers = actionsOf<StartTransfer>(actions);
  ASSERT_EQ(transfers.size(), 1u);
  EXPECT_EQ(transfers[0].peer, peer);
  EXPECT_EQ(transfers[0].target, full() / 2);
  EXPECT_EQ(transfers[0].transferId, 1u);

  actions = engine().onMessage(peer, ResolutionRequest{full() / 2 - 1}, now());
  EXPECT_TRUE(actionsOf<StartTransfer>(actions).empty()) << "already on its way";

  actions = engine().onTransferFinished(peer, now());
  const std::vector<Keyframe> keyframes = sentTo<Keyframe>(actions, peer);
  ASSERT_EQ(keyframes.size(), 1u);
  EXPECT_EQ(keyframes[0].frame, engine().currentFrame());
  const std::vector<PeerList> lists = sentToAll<PeerList>(actions);
  ASSERT_EQ(lists.size(), 1u);
  EXPECT_EQ(lists[0].peers[1].vertexCount, full() / 2 - 1) << "its level, exactly";
  EXPECT_EQ(engine().counters().transfersCompleted, 1u);

  actions = engine().onMessage(peer, ResolutionRequest{full() / 2 - 1}, now());
  const std::vector<StartTransfer> again = actionsOf<StartTransfer>(actions);
  ASSERT_EQ(again.size(), 1u) << "a built level starts at once";
  EXPECT_EQ(again[0].transferId, 2u);
}

TEST_F(HostEnginePeers, FailedLevelFallsBackToTheFullModel) {
  startWithLadder();
  const PeerId peer = join(QStringLiteral("alice"));
  engine().onMessage(peer, ResolutionRequest{full() / 20}, now());
  HostActions actions = engine().onLevelFailed(full() / 20, QStringLiteral("no mesh"), now());
  const std::vector<RequestLevel> requests = actionsOf<RequestLevel>(actions);
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].target, full());
  actions = engine().onLevelReady(full(), {full(), 320, 9000}, now());
  const std::vector<StartTransfer> transfers = actionsOf<StartTransfer>(actions);
  ASSERT_EQ(transfers.size(), 1u);
  EXPECT_EQ(transfers[0].target, full());
  EXPECT_EQ(sentToAll<LevelList>(actions).at(0).levels.size(), 1u) << "the failed rung stays unlisted";
}

TEST_F(HostEnginePeers, LockRequestsAreArbitratedAndReleasedOnClose) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  HostActions actions = engine().onMessage(alice, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  const std::vector<LockNotice> granted = sentToAll<LockNotice>(actions);
  ASSERT_EQ(granted.size(), 1u);
  EXPECT_EQ(granted[0].kind, LockNoticeKind::Granted);
  EXPECT_EQ(granted[0].peer, alice);
  EXPECT_EQ(actionsOf<LockChanged>(actions).size(), 1u);
  actions = engine().onMessage(bob, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  const std::vector<LockNotice> queued = sentTo<LockNotice>(actions, bob);
  ASSERT_EQ(queued.size(), 1u);
  EXPECT_EQ(queued[0].kind, LockNoticeKind::Queued);

  actions = engine().onClosed(alice, now());
  EXPECT_EQ(engine().arbiter().holder(), bob) << "the queue's head gets the lock";
  EXPECT_EQ(sentToAll<PeerList>(actions).at(0).peers.size(), 2u);
}

TEST_F(HostEnginePeers, DragsAreCheckedAgainstTheLock) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  Drag drag;
  drag.epoch = 1;
  engine().onMessage(alice, drag, now());
  EXPECT_EQ(engine().counters().dragsNotHolder, 1u);
  engine().onMessage(alice, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  drag.epoch = 7;
  engine().onMessage(alice, drag, now());
  EXPECT_EQ(engine().counters().dragsStale, 1u);
  Constraints constraints;
  constraints.epoch = 1;
  constraints.groups = {{0, full()}};
  engine().onMessage(alice, constraints, now());
  EXPECT_EQ(engine().counters().constraintsRejected, 1u) << "a vertex id ≥ n";
  constraints.groups.assign(1, {});
  for (Eigen::Index i = 0; i < s_model->V.rows(); ++i) {
    if (s_model->V(i, 2) > 0.8) constraints.groups[0].push_back(static_cast<std::uint32_t>(i));
    if (s_model->V(i, 2) < -0.5) constraints.anchors.push_back(static_cast<std::uint32_t>(i));
  }
  completeConstraints(engine().onMessage(alice, constraints, now()));  // factored off the network thread
  EXPECT_EQ(engine().counters().constraintsAccepted, 1u);
  drag.epoch = 1;
  spectral::HandleTransform pose;
  pose.translation = Eigen::Vector3d(0.0, 0.0, 0.1);
  drag.handles = {toWire(0, pose)};
  EXPECT_EQ(actionsOf<SendFrame>(engine().onMessage(alice, drag, now())).size(), 1u) << "the holder's drag";
  EXPECT_EQ(engine().counters().dragsAccepted, 1u);
}

TEST_F(HostEnginePeers, PeersMessagesStatsLeaveAndProtocolErrors) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  StatsReport report;
  report.framesApplied = 42;
  const std::vector<StatsReported> stats = actionsOf<StatsReported>(engine().onMessage(alice, report, now()));
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_EQ(stats[0].report.framesApplied, 42u);
  EXPECT_EQ(engine().stats(alice)->framesApplied, 42u);

  const std::vector<ClosePeer> left = actionsOf<ClosePeer>(engine().onMessage(alice, Leave{}, now()));
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].how, ClosePeer::How::Abort);

  const std::vector<ClosePeer> failed =
      actionsOf<ClosePeer>(engine().onMessage(bob, Hello{kProtocolVersion, QStringLiteral("again")}, now()));
  ASSERT_EQ(failed.size(), 1u) << "a Hello after the Welcome is a protocol error";
  EXPECT_EQ(failed[0].how, ClosePeer::How::Graceful);
  EXPECT_EQ(engine().counters().protocolErrors, 1u);
  EXPECT_TRUE(engine().onMessage(bob, StatsReport{}, now()).list.empty()) << "a closing peer is not heard";
}

}  // namespace
}  // namespace sc::session::testing
