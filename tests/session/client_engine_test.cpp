// Tests for the ClientEngine's state machine, failure texts and refusals (src/session/engine/client_engine.cpp),
// driven by a fake host with an injected clock: no sockets, no timers.
#include "client_engine_fixture.h"

namespace sc::session::test {
namespace {

using S = ClientState;

TEST(ClientEngine, JoinsThroughConnectingHandshakingAndLoading) {
  ClientEngine engine(config("ann", 1200));
  ClientActions out = engine.start();
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Connecting});
  EXPECT_EQ(actionsOf<client_action::Connect>(out).size(), 1u);
  EXPECT_TRUE(engine.start().empty()) << "start() from Idle only";

  out = engine.onSecured(QByteArray(32, 'c'), kT0);
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Handshaking});
  ASSERT_EQ(sent<Hello>(out).size(), 1u);
  EXPECT_EQ(sent<Hello>(out)[0].displayName, QStringLiteral("ann"));

  out = engine.onMessage(message(fakeWelcome()), kT0);
  ASSERT_EQ(actionsOf<client_action::OpenDatagrams>(out).size(), 1u) << "the datagram path first";
  EXPECT_EQ(actionsOf<client_action::OpenDatagrams>(out)[0].session, fakeWelcome());
  EXPECT_EQ(engine.state(), S::Handshaking) << "Loading only once the datagrams are open";
  ASSERT_NE(engine.lock(), nullptr);
  EXPECT_EQ(engine.lock()->self(), kSelf);

  out = engine.onDatagramsOpened(kT0);
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Loading});
  EXPECT_EQ(sent<ResolutionRequest>(out), std::vector<ResolutionRequest>{{1200}});
  EXPECT_TRUE(engine.onDatagramsOpened(kT0).empty()) << "once";
}

TEST(ClientEngine, LevelFractionIsRoundedAgainstTheWelcomesVertexCount) {
  const auto request = [](double fraction) {
    ClientEngine engine(config("f", 77, fraction));
    return sent<ResolutionRequest>(joinSession(engine)).at(0).vertexCount;
  };
  EXPECT_EQ(request(0.5), 2u);  // round(0.5 · 3)
  EXPECT_EQ(request(0.2), 1u);  // round(0.6)
  EXPECT_EQ(request(1.0), 0u) << "1 or more: full";
  EXPECT_EQ(request(0.0), 0u) << "not > 0: full";
}

TEST(ClientEngine, ARefusalFailsWithTheHostsText) {
  ClientEngine engine(config("bob"));
  engine.start();
  engine.onSecured({}, kT0);
  const ClientActions out = engine.onMessage(
      message(Refused{RefuseReason::SessionFull, kProtocolVersion, QStringLiteral("room is full")}), kT0);
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Failed});
  ASSERT_EQ(actionsOf<client_action::Failed>(out).size(), 1u);
  EXPECT_EQ(actionsOf<client_action::Failed>(out)[0].reason, engine.errorText());
  EXPECT_TRUE(engine.errorText().contains(QStringLiteral("room is full"))) << engine.errorText().toStdString();
  EXPECT_EQ(actionsOf<client_action::Disconnect>(out).size(), 1u);
  EXPECT_FALSE(actionsOf<client_action::Disconnect>(out)[0].flush);
  EXPECT_EQ(engine.onClosed().size(), 0u) << "Failed is final";
}

TEST(ClientEngine, AChallengeWithoutAPasswordOrGarbageFailsTheHandshakeLocally) {
  ClientEngine engine(config("nopass"));
  engine.start();
  engine.onSecured({}, kT0);
  const ClientActions out =
      engine.onMessage(message(Challenge{QByteArray(kNonceSize, 'n'), QByteArray(kSaltSize, 's'), 16}), kT0);
  EXPECT_TRUE(sentMessages(out).empty()) << "the password is never guessed";
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Failed});
  EXPECT_EQ(engine.handshake().failure(), ClientFailure::PasswordRequired);
  EXPECT_EQ(engine.errorText(), engine.handshake().errorText());

  ClientEngine garbage(config("garbage"));
  garbage.start();
  garbage.onSecured({}, kT0);
  garbage.onMessage(ControlDecodeResult{ControlError::UnknownType, {}}, kT0);
  EXPECT_EQ(garbage.state(), S::Failed);
  EXPECT_EQ(garbage.handshake().failure(), ClientFailure::ProtocolError);
}

TEST(ClientEngine, ClosedConnectionReadsHostLostOnceJoined) {
  ClientEngine handshaking(config("a"));
  handshaking.start();
  handshaking.onSecured({}, kT0);
  handshaking.onClosed();
  EXPECT_EQ(handshaking.errorText(), QStringLiteral("the host closed the connection"));

  ClientEngine joined(config("b"));
  joinSession(joined);
  const ClientActions out = joined.onClosed();
  EXPECT_EQ(joined.state(), S::Failed);
  EXPECT_EQ(joined.errorText(), QStringLiteral("host lost: the connection to the host closed without warning"));
  EXPECT_EQ(actionsOf<client_action::CloseDatagrams>(out).size(), 1u);

  ClientEngine errored(config("c"));
  joinSession(errored);
  errored.onTransportError(QStringLiteral("Connection reset"));
  EXPECT_EQ(errored.errorText(), QStringLiteral("host lost: Connection reset"));
  ClientEngine connecting(config("d"));
  connecting.start();
  connecting.onTransportError(QStringLiteral("Connection refused"));
  EXPECT_EQ(connecting.errorText(), QStringLiteral("Connection refused"));
}

TEST(ClientEngine, ProtocolErrorsAndUnexpectedMessagesFailTheSession) {
  ClientEngine malformed(config("a"));
  joinSession(malformed);
  malformed.onMessage(ControlDecodeResult{ControlError::Malformed, {}}, kT0);
  EXPECT_EQ(malformed.errorText(), QStringLiteral("protocol error from the host: malformed"));

  ClientEngine unexpected(config("b"));
  joinSession(unexpected);
  unexpected.onMessage(message(Hello{}), kT0);
  EXPECT_EQ(unexpected.state(), S::Failed);
  EXPECT_TRUE(unexpected.errorText().startsWith(QStringLiteral("protocol error from the host: unexpected message 0x")))
      << unexpected.errorText().toStdString();
  EXPECT_TRUE(unexpected.onMessage(message(Heartbeat{}), kT0).empty()) << "nothing after a failure";
}

TEST(ClientEngine, LeaveEitherWayEndsInLeft) {
  ClientEngine ours(config("a"));
  joinSession(ours);
  ClientActions out = ours.leave();
  EXPECT_EQ(sentMessages(out).size(), 1u);
  EXPECT_EQ(sent<Leave>(out).size(), 1u);
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Left});
  ASSERT_EQ(actionsOf<client_action::Disconnect>(out).size(), 1u);
  EXPECT_TRUE(actionsOf<client_action::Disconnect>(out)[0].flush) << "the Leave is written first";
  EXPECT_EQ(ours.errorText(), QStringLiteral("left the session"));
  EXPECT_TRUE(ours.leave().empty());
  EXPECT_TRUE(ours.onClosed().empty()) << "our own disconnect is no failure";

  ClientEngine handshaking(config("b"));
  handshaking.start();
  handshaking.onSecured({}, kT0);
  out = handshaking.leave();
  EXPECT_TRUE(sentMessages(out).empty()) << "no Leave during the handshake: just close";
  EXPECT_EQ(handshaking.state(), S::Left);
  EXPECT_TRUE(ClientEngine(config("c")).leave().empty()) << "nothing from Idle";

  ClientEngine theirs(config("d"));
  joinSession(theirs);
  out = theirs.onMessage(message(Leave{LeaveReason::HostEnded, {}}), kT0);
  EXPECT_EQ(statesOf(out), std::vector<S>{S::Left});
  EXPECT_EQ(theirs.errorText(), QStringLiteral("The host ended the session."));
  EXPECT_EQ(theirs.leaveReason(), LeaveReason::HostEnded);
  EXPECT_TRUE(actionsOf<client_action::Failed>(out).empty());
}

TEST(ClientEngine, TheHostsLeaveReasonIsReadNotTakenForALostHost) {
  ClientEngine kicked(config("a"));
  joinSession(kicked);
  ClientActions out = kicked.onMessage(message(Leave{LeaveReason::Kicked, QStringLiteral("be nice")}), kT0);
  EXPECT_EQ(statesOf(out), std::vector<ClientState>{ClientState::Left});
  EXPECT_EQ(kicked.errorText(), QStringLiteral("The host removed you from the session. (be nice)"));
  EXPECT_EQ(kicked.leaveReason(), LeaveReason::Kicked);
  EXPECT_TRUE(kicked.onClosed().empty()) << "the close after the Leave is no failure";

  ClientEngine lost(config("b"));
  joinSession(lost);
  lost.onClosed();
  EXPECT_EQ(lost.state(), ClientState::Failed);
  EXPECT_EQ(lost.errorText(), QStringLiteral("host lost: the connection to the host closed without warning"));
  EXPECT_FALSE(lost.leaveReason().has_value());

  ClientEngine leaving(config("c"));
  joinSession(leaving);
  const std::vector<Leave> leaves = sent<Leave>(leaving.leave());
  ASSERT_EQ(leaves.size(), 1u);
  EXPECT_EQ(leaves[0].reason, LeaveReason::ClientLeft);
}

TEST(ClientEngine, TheHolderLearnsWhoWaitsForTheLock) {
  ClientEngine engine(config("a"));
  joinSession(engine);
  engine.requestLock(kT0);
  engine.onMessage(message(LockNotice{LockNoticeKind::Granted, kSelf, 4}), kT0);
  ASSERT_TRUE(engine.lock()->canDrag());
  const ClientActions out =
      engine.onMessage(message(LockNotice{LockNoticeKind::Waiting, kNoPeer, kNoEpoch, 0, {}, {7, 9}}), kT0);
  EXPECT_EQ(engine.lock()->waiting(), (std::vector<PeerId>{7, 9}));
  EXPECT_EQ(actionsOf<client_action::Notify>(out).at(0).notice, ClientNotice::LockChanged) << "the window redraws";
  EXPECT_TRUE(sentMessages(out).empty()) << "nothing to answer";
  EXPECT_TRUE(engine.lock()->canDrag());
}

TEST(ClientEngine, CommandsAreRefusedUnlessLiveAndDragsUnlessHeld) {
  ClientEngine engine(config("a"));
  EXPECT_TRUE(engine.requestResolution(10).empty());
  EXPECT_TRUE(engine.requestLock(kT0).empty());
  joinSession(engine);
  EXPECT_EQ(sent<ResolutionRequest>(engine.requestResolution(10)), std::vector<ResolutionRequest>{{10}});
  EXPECT_TRUE(engine.sendDrag({HandleTransform{}}).empty()) << "no lock";
  EXPECT_TRUE(engine.sendConstraints({{1}}, {}).empty()) << "no lock";
  ClientActions out = engine.requestLock(kT0);
  EXPECT_EQ(sent<LockMessage>(out), (std::vector<LockMessage>{{LockRequestKind::Request, kNoEpoch}}));
  EXPECT_EQ(actionsOf<client_action::Notify>(out).at(0).notice, ClientNotice::LockChanged);
  EXPECT_TRUE(engine.requestLock(kT0).empty()) << "already asked";
  engine.onMessage(message(LockNotice{LockNoticeKind::Granted, kSelf, 9}), kT0);
  ASSERT_TRUE(engine.lock()->canDrag());
  EXPECT_EQ(sent<Drag>(engine.sendDrag({HandleTransform{}})).at(0).epoch, 9u) << "stamped with the held epoch";
  EXPECT_EQ(sent<Constraints>(engine.sendConstraints({{1, 2}}, {0})).at(0).epoch, 9u);
  out = engine.releaseLock(kT0);
  EXPECT_EQ(sent<LockMessage>(out), (std::vector<LockMessage>{{LockRequestKind::Release, 9}}));
  EXPECT_TRUE(engine.sendDrag({HandleTransform{}}).empty()) << "released";
}

TEST(ClientEngine, PeerAndLevelListsAreKeptAndAnnounced) {
  ClientEngine engine(config("a"));
  joinSession(engine);
  const PeerList peers{{PeerInfo{kSelf, 3, QStringLiteral("a")}}};
  ClientActions out = engine.onMessage(message(peers), kT0);
  EXPECT_EQ(engine.peers(), peers);
  EXPECT_EQ(actionsOf<client_action::Notify>(out).at(0).notice, ClientNotice::PeersChanged);
  const LevelList levels{2, {LevelInfo{0, 3, 1, 200}}};  // 200 bytes: within what 3 vertices, 1 face, m = 2 imply
  out = engine.onMessage(message(levels), kT0);
  EXPECT_EQ(engine.levels(), levels);
  EXPECT_EQ(actionsOf<client_action::Notify>(out).at(0).notice, ClientNotice::LevelsChanged);
}

}  // namespace
}  // namespace sc::session::test
