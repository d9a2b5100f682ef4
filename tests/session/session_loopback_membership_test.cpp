// Loopback tests of who gets into a session and who stays (src/session/net/session_host.cpp, session_client.cpp,
// host_peer_connection.cpp): peer lists as clients join and leave, a taken name, a wrong or missing password, a
// protocol version mismatch, garbage on the control connection, a silent peer. Real TCP and UDP sockets on 127.0.0.1;
// hand-written peers (RawPeer) send what SessionClient never would. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include "session/wire/control_frame.h"

#include <QtCore/QtEndian>
#include <QtTest/QTest>

namespace sc::session {
namespace {

TEST_F(SessionLoopback, JoinAndLeaveUpdatePeerLists) {
  auto host = startHost();
  auto alice = join(*host, QStringLiteral("alice"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return alice->peers().peers.size() == 2; }, kWaitMs));
  EXPECT_EQ(alice->peers().peers[0].peerId, kHostPeer);
  EXPECT_EQ(alice->peers().peers[0].name, QStringLiteral("Hostess"));
  EXPECT_EQ(alice->peerId(), 2u);

  auto bob = join(*host, QStringLiteral("bob"));
  EXPECT_EQ(bob->peerId(), 3u);
  // Bob's entry carries his level once his transfer is complete; everybody ends with the host's list.
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return alice->peers() == host->peerList() && bob->peers() == host->peerList(); }, kWaitMs));
  ASSERT_EQ(bob->peers().peers.size(), 3u);
  EXPECT_EQ(bob->peers().peers[2].name, QStringLiteral("bob"));
  EXPECT_EQ(bob->peers().peers[2].vertexCount, n());

  bob->leave();
  EXPECT_EQ(bob->state(), SessionClient::State::Left);
  ASSERT_TRUE(QTest::qWaitFor([&] { return alice->peers().peers.size() == 2; }, kWaitMs));
  EXPECT_EQ(host->peerList().peers.size(), 2u);

  // A taken name is refused.
  auto twin = connectClient(*host, QStringLiteral("alice"));
  EXPECT_FALSE(waitReady(*twin));
  ASSERT_TRUE(twin->handshake().refusal().has_value());
  EXPECT_EQ(twin->handshake().refusal()->reason, RefuseReason::BadName);

  // Host shutdown: Leave to everybody.
  host->shutdown();
  ASSERT_TRUE(QTest::qWaitFor([&] { return alice->state() == SessionClient::State::Left; }, kWaitMs));
  EXPECT_EQ(alice->errorText(), QStringLiteral("The host ended the session."));
}

TEST_F(SessionLoopback, WrongPasswordIsRefusedWithItsReason) {
  SessionHostOptions options = hostOptions();
  options.password = QStringLiteral("open sesame");
  auto host = startHost(options);

  auto wrong = connectClient(*host, QStringLiteral("mallory"), 0, QStringLiteral("open barley"));
  EXPECT_FALSE(waitReady(*wrong));
  EXPECT_EQ(wrong->state(), SessionClient::State::Failed);
  ASSERT_TRUE(wrong->handshake().refusal().has_value());
  EXPECT_EQ(wrong->handshake().refusal()->reason, RefuseReason::WrongPassword);
  EXPECT_EQ(wrong->errorText(), wrong->handshake().refusal()->text);
  EXPECT_FALSE(wrong->errorText().isEmpty());
  EXPECT_EQ(host->counters().refusalsFor(RefuseReason::WrongPassword), 1u);

  auto none = connectClient(*host, QStringLiteral("nopass"));
  EXPECT_FALSE(waitReady(*none));
  EXPECT_EQ(none->handshake().failure(), ClientFailure::PasswordRequired);

  auto right = connectClient(*host, QStringLiteral("alice"), 0, QStringLiteral("open sesame"));
  EXPECT_TRUE(waitReady(*right)) << right->errorText().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 2; }, kWaitMs));
}

TEST_F(SessionLoopback, VersionMismatchIsRefusedBeforeAnythingElse) {
  auto host = startHost();
  RawPeer peer(host->tcpPort());
  ASSERT_TRUE(peer.connected());
  // Hello of a hypothetical version 99, built by hand: u32 length · u8 type · magic · version · nameLen · name.
  QByteArray hello;
  const QByteArray body = QByteArray::fromHex("5343") + char(99) + char(3) + QByteArray("bob") + QByteArray("future");
  hello.resize(4);
  qToBigEndian<quint32>(static_cast<quint32>(1 + body.size()), hello.data());
  hello += char(0x40);
  hello += body;
  peer.sendRaw(hello);
  const std::optional<Refused> refused = peer.take<Refused>();
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RefuseReason::VersionMismatch);
  EXPECT_EQ(refused->hostVersion, kProtocolVersion);
  EXPECT_TRUE(refused->text.contains(QStringLiteral("99"))) << refused->text.toStdString();
  EXPECT_TRUE(peer.closedByHost());
  EXPECT_FALSE(peer.take<Welcome>(100).has_value());
  EXPECT_EQ(host->counters().refusalsFor(RefuseReason::VersionMismatch), 1u);
}

TEST_F(SessionLoopback, GarbageAfterWelcomeClosesTheConnection) {
  auto host = startHost();
  RawPeer raw(host->tcpPort());
  ASSERT_TRUE(raw.join(QStringLiteral("raw")).has_value());
  raw.sendRaw(QByteArray::fromHex("ffffffff00"));  // length beyond the limit
  EXPECT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().protocolErrors, 1u);

  // Before the Welcome the same earns a Refused(ProtocolError).
  RawPeer early(host->tcpPort());
  ASSERT_TRUE(early.connected());
  early.sendRaw(QByteArray::fromHex("0000000140"));  // a Hello without a body
  const std::optional<Refused> refused = early.take<Refused>();
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RefuseReason::ProtocolError);
  EXPECT_TRUE(early.closedByHost());
}

TEST_F(SessionLoopback, SilentPeerIsDropped) {
  SessionHostOptions options = hostOptions();
  options.peerTimeout = std::chrono::milliseconds(1500);
  auto host = startHost(options);
  RawPeer raw(host->tcpPort());  // never sends a heartbeat
  ASSERT_TRUE(raw.join(QStringLiteral("quiet")).has_value());
  EXPECT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().silentPeersDropped, 1u);
}

}  // namespace
}  // namespace sc::session
