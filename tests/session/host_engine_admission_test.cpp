// Tests for src/session/engine/host_engine.cpp and host_engine_peers.cpp: admission limits, peer ids, the handshake
// deadline, heartbeats and the silent-peer timeout, shutdown; with a fake clock and no sockets.
#include "host_engine_fixture.h"

namespace sc::session::testing {
namespace {

using HostEngineAdmission = HostEngineTest;

TEST_F(HostEngineAdmission, LimitsPendingHandshakesInAllAndPerAddress) {
  HostEngineOptions options;
  options.maxPendingHandshakes = 3;
  options.maxPendingPerAddress = 2;
  startEngine(options);
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.1", now()).peer, 2);
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.1", now()).peer, 3);
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.1", now()).peer, kNoPeer) << "a third from one address";
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.2", now()).peer, 4);
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.2", now()).peer, kNoPeer) << "a fourth in all";
  EXPECT_EQ(engine().counters().connectionsOverLimit, 2u);

  engine().onWelcomed(2, QStringLiteral("welcomed"), now());
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.1", now()).peer, 5) << "a welcomed peer no longer counts";
  engine().onRefused(3, RefuseReason::WrongPassword, now());
  EXPECT_EQ(engine().counters().refusalsFor(RefuseReason::WrongPassword), 1u);
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.3", now()).peer, 6) << "nor does a refused one (closing)";
}

TEST_F(HostEngineAdmission, PeerIdsSkipIdsInUseAndMarkAFullSession) {
  HostEngineOptions options;
  options.maxPeers = 2;
  startEngine(options);
  const PeerId first = join(QStringLiteral("a"));
  const PeerId second = join(QStringLiteral("b"));
  EXPECT_EQ(first, 2);
  EXPECT_EQ(second, 3);
  const Admission third = engine().onConnectionAttempt("10.0.0.9", now());
  EXPECT_EQ(third.peer, 4);
  EXPECT_TRUE(engine().sessionFull()) << "maxPeers members: the handshake refuses the third after its proof";
  engine().onClosed(third.peer, now());
  engine().onClosed(first, now());
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.9", now()).peer, 5) << "ids are not reused at once";
  for (PeerId id = 6; id != 3; id = id >= 0xffff ? 2 : id + 1) {
    const Admission admission = engine().onConnectionAttempt("10.0.0.9", now());
    ASSERT_EQ(admission.peer, id);
    engine().onClosed(admission.peer, now());
  }
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.9", now()).peer, 4) << "after the wrap, 3 and 5 are in use";
  EXPECT_TRUE(engine().nameTaken(QStringLiteral("b")));
  EXPECT_TRUE(engine().nameTaken(QStringLiteral("host"))) << "the host's own name";
  EXPECT_FALSE(engine().nameTaken(QStringLiteral("a"))) << "a left";
}

TEST_F(HostEngineAdmission, HandshakeExpiresStrictlyAfterTheTimeout) {
  HostEngineOptions options;
  options.handshakeTimeout = 500ms;
  startEngine(options);
  const Micros accepted = now();
  const PeerId slow = engine().onConnectionAttempt("10.0.0.1", now()).peer;
  const PeerId quick = join(QStringLiteral("quick"));
  EXPECT_TRUE(actionsOf<ExpireHandshake>(tickUntil(accepted + 500ms)).empty()) << "500 ms is not yet over";
  const std::vector<ExpireHandshake> expired = actionsOf<ExpireHandshake>(tickUntil(accepted + 600ms));
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired[0].peer, slow) << "the welcomed one never expires (" << quick << ")";
  engine().onRefused(slow, RefuseReason::ProtocolError, now());  // what the expired handshake does
  EXPECT_TRUE(actionsOf<ExpireHandshake>(tickFor(1s)).empty()) << "once";
}

TEST_F(HostEngineAdmission, HeartbeatEachSecondToWelcomedPeers) {
  startEngine();
  const PeerId peer = join(QStringLiteral("peer"));
  const PeerId pending = engine().onConnectionAttempt("10.0.0.2", now()).peer;
  const Micros started = now();
  HostActions actions = tickUntil(started + 999ms);
  EXPECT_TRUE(sentTo<Heartbeat>(actions, peer).empty());
  actions = tickUntil(started + 2s);
  const std::vector<Heartbeat> beats = sentTo<Heartbeat>(actions, peer);
  ASSERT_EQ(beats.size(), 2u);
  EXPECT_EQ(beats[0].sequence, 0u);
  EXPECT_EQ(beats[1].sequence, 1u);
  EXPECT_TRUE(sentTo<Heartbeat>(actions, pending).empty()) << "not before the Welcome";
}

TEST_F(HostEngineAdmission, SilentPeerIsDroppedAfterThePeerTimeout) {
  HostEngineOptions options;
  options.peerTimeout = 2500ms;
  startEngine(options);
  const Micros started = now();
  const PeerId silent = join(QStringLiteral("silent"));
  const PeerId chatty = join(QStringLiteral("chatty"));
  engine().onHeard(chatty, started + 2500ms);
  EXPECT_TRUE(actionsOf<ClosePeer>(tickUntil(started + 2s)).empty()) << "2 s of silence is within 2.5 s";
  const HostActions actions = tickUntil(started + 3s);
  const std::vector<ClosePeer> closed = actionsOf<ClosePeer>(actions);
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_EQ(closed[0].peer, silent);
  EXPECT_EQ(closed[0].how, ClosePeer::How::Abort);
  EXPECT_TRUE(sentTo<Heartbeat>(actions, silent).empty());
  EXPECT_EQ(sentTo<Heartbeat>(actions, chatty).size(), 1u);
  EXPECT_EQ(engine().counters().silentPeersDropped, 1u);
  EXPECT_EQ(engine().peerList().peers.size(), 2u) << "a closing peer is no longer listed";
}

TEST_F(HostEngineAdmission, ShutdownSaysGoodbyeAndStopsEverything) {
  startEngine();
  const PeerId member = join(QStringLiteral("member"));
  const PeerId pending = engine().onConnectionAttempt("10.0.0.2", now()).peer;
  const HostActions actions = engine().shutdown(now());
  EXPECT_EQ(sentTo<Leave>(actions, member).size(), 1u);
  const std::vector<Refused> refused = sentTo<Refused>(actions, pending);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].reason, RefuseReason::ShuttingDown);
  EXPECT_EQ(actionsOf<ClosePeer>(actions).size(), 2u);
  EXPECT_FALSE(actions.wakeAt.has_value()) << "no more ticks";
  EXPECT_EQ(engine().onConnectionAttempt("10.0.0.3", now()).peer, kNoPeer);
  EXPECT_EQ(engine().counters().connectionsOverLimit, 0u) << "refused for shutting down, not over a limit";
  EXPECT_TRUE(engine().tick(now() + 5s).list.empty());
}

}  // namespace
}  // namespace sc::session::testing
