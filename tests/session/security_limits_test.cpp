// Limits a session host keeps against abuse (docs/security.md): an oversized control message closes only that
// connection, connections over the per-address limit are closed while an honest client joins, and pending
// (unauthenticated) connections are capped and closed at the handshake deadline. Real TLS over loopback sockets
// (127.0.0.2 as "another address"). Fixture: security_fixture.h.
#include "security_fixture.h"

#include "raw_control_peer.h"
#include "silent_connections.h"

#include <QtCore/QtEndian>
#include <QtNetwork/QTcpSocket>
#include <QtTest/QTest>

#include <algorithm>
#include <vector>

namespace sc::session {
namespace {

TEST_F(Security, OversizedMessageClosesThatConnectionAndTheHostKeepsServing) {
  auto host = startHost(hostOptions(std::nullopt));
  auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest"), std::nullopt));
  ASSERT_TRUE(settle(*honest)) << honest->errorText().toStdString();
  QByteArray header(5, '\0');
  qToBigEndian<quint32>(kMaxControlMessageSize + 1, header.data());
  header[4] = 0x10;
  // Before the Welcome and after it.
  testing::RawControlPeer early(host->tcpPort());
  ASSERT_TRUE(early.connected());
  early.sendRaw(header);
  EXPECT_TRUE(early.closedByHost());
  testing::RawControlPeer member(host->tcpPort());
  ASSERT_TRUE(member.join(QStringLiteral("member")));
  member.sendRaw(header + QByteArray(64 * 1024, 'x'));
  EXPECT_TRUE(member.closedByHost());
  EXPECT_EQ(host->counters().oversizeMessages, 2u);
  const std::uint64_t applied = honest->channel().framesApplied();
  EXPECT_TRUE(QTest::qWaitFor([&] { return honest->channel().framesApplied() > applied + 3; }, kWaitMs));
  EXPECT_EQ(honest->state(), SessionClient::State::Ready);
  auto later = start(clientOptions(host->tcpPort(), QStringLiteral("later"), std::nullopt));
  EXPECT_TRUE(settle(*later)) << later->errorText().toStdString();
}

int stillOpen(const std::vector<std::unique_ptr<QTcpSocket>>& sockets) {
  return static_cast<int>(std::count_if(sockets.begin(), sockets.end(),
                                        [](const auto& s) { return s->state() != QAbstractSocket::UnconnectedState; }));
}

TEST_F(Security, ConnectionsOverThePerAddressLimitAreClosedWhileAnHonestClientJoins) {
  SessionHostOptions options = hostOptions();
  options.maxPendingPerAddress = 4;
  auto host = startHost(options);
  const auto sockets = testing::openSilentConnections(QHostAddress(QStringLiteral("127.0.0.2")), host->tcpPort(), 10);
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().connectionsOverLimit == 6; }, kWaitMs));
  EXPECT_TRUE(QTest::qWaitFor([&] { return stillOpen(sockets) == 4; }, kWaitMs));
  auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest")));
  EXPECT_TRUE(settle(*honest)) << honest->errorText().toStdString();
  EXPECT_EQ(stillOpen(sockets), 4);  // the admitted ones wait for their deadline
}

TEST_F(Security, PendingConnectionsAreCappedAndClosedAtTheHandshakeDeadline) {
  SessionHostOptions options = hostOptions();
  options.maxPendingHandshakes = 3;
  options.handshakeTimeout = std::chrono::milliseconds(1000);
  auto host = startHost(options);
  const auto sockets = testing::openSilentConnections(QHostAddress(QStringLiteral("127.0.0.2")), host->tcpPort(), 5);
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().connectionsOverLimit == 2; }, kWaitMs));
  // A TLS peer that completes TLS but never says Hello is closed at the deadline too.
  testing::RawControlPeer silent(host->tcpPort());
  EXPECT_TRUE(silent.closedByHost());
  EXPECT_TRUE(QTest::qWaitFor([&] { return stillOpen(sockets) == 0; }, kWaitMs));
  EXPECT_GE(host->counters().refusalsFor(RefuseReason::ProtocolError), 3u);  // "handshake timed out"
  auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest")));
  EXPECT_TRUE(settle(*honest)) << honest->errorText().toStdString();
}

}  // namespace
}  // namespace sc::session
