// What a stranger cannot do (docs/security.md): without the password it can neither join, see the model, take the
// lock nor move the shape, and the host sends no datagram to an address that did not prove its path token (no
// amplification). Real TLS and UDP over loopback sockets. Fixture: security_fixture.h.
#include "security_fixture.h"

#include "raw_control_peer.h"
#include "session/net/host_datagram_channel.h"
#include "session/wire/path_open.h"

#include <QtNetwork/QNetworkDatagram>
#include <QtNetwork/QUdpSocket>
#include <QtTest/QTest>

namespace sc::session {
namespace {

TEST_F(Security, StrangerCannotJoinSeeTheModelOrMoveIt) {
  auto host = startHost();
  auto member = start(clientOptions(host->tcpPort(), QStringLiteral("member")));
  ASSERT_TRUE(settle(*member)) << member->errorText().toStdString();
  // Wrong password, and no password: refused with the reason.
  auto guesser = start(clientOptions(host->tcpPort(), QStringLiteral("guesser"), QStringLiteral("hunter2")));
  EXPECT_FALSE(settle(*guesser));
  EXPECT_EQ(guesser->errorText(), QStringLiteral("wrong password"));
  auto blank = start(clientOptions(host->tcpPort(), QStringLiteral("blank"), std::nullopt));
  EXPECT_FALSE(settle(*blank));
  EXPECT_TRUE(blank->errorText().contains(QStringLiteral("password")));
  EXPECT_TRUE(guesser->levelPayload().isEmpty() && blank->levelPayload().isEmpty());
  // A hand-made stranger skips the proof: asks for the model, takes the lock, drags. Refused, closed, nothing sent.
  testing::RawControlPeer stranger(host->tcpPort());
  ASSERT_TRUE(stranger.connected());
  stranger.send(Hello{kProtocolVersion, QStringLiteral("stranger")});
  ASSERT_TRUE(stranger.take<Challenge>());
  stranger.send(ResolutionRequest{});
  stranger.send(LockMessage{LockRequestKind::Request, kNoEpoch});
  stranger.send(Drag{1, {HandleTransform{}}});
  EXPECT_TRUE(stranger.closedByHost());
  EXPECT_FALSE(stranger.take<ModelBegin>(0));
  EXPECT_FALSE(stranger.take<PeerList>(0));
  EXPECT_FALSE(stranger.take<Welcome>(0));
  EXPECT_FALSE(stranger.take<ModelChunk>(0));
  EXPECT_EQ(host->counters().dragsAccepted, 0u);
  EXPECT_EQ(host->lockHolder(), kNoPeer);
  EXPECT_TRUE(host->coefficients().isZero());
  EXPECT_EQ(members(*host), 1u);
  EXPECT_EQ(member->state(), SessionClient::State::Ready);
}

TEST_F(Security, HostSendsNoDatagramToAnAddressThatDidNotProveItsToken) {
  auto host = startHost();
  auto member = start(clientOptions(host->tcpPort(), QStringLiteral("member")));
  ASSERT_TRUE(settle(*member)) << member->errorText().toStdString();
  QUdpSocket stranger;
  ASSERT_TRUE(stranger.bind(QHostAddress::LocalHost, 0));
  qint64 receivedBytes = 0;
  QObject::connect(&stranger, &QUdpSocket::readyRead, &stranger, [&] {
    while (stranger.hasPendingDatagrams()) receivedBytes += stranger.receiveDatagram().data().size();
  });
  // A PathOpen for the member's peer id with a guessed token and key, one with garbage, one replayed-looking.
  const PeerId id = member->peerId();
  const QByteArray forged = encodePathOpen(id, QByteArray(kPathTokenSize, '\x01'), 1, QByteArray(32, '\x02'));
  qint64 sentBytes = 0;
  for (int i = 0; i < 50; ++i) {
    sentBytes += stranger.writeDatagram(forged, QHostAddress::LocalHost, host->udpPort());
    sentBytes +=
        stranger.writeDatagram(QByteArray(100, static_cast<char>(i)), QHostAddress::LocalHost, host->udpPort());
  }
  const std::uint64_t framesBefore = host->counters().framesSent;
  QTest::qWait(1000);
  EXPECT_GT(host->counters().framesSent, framesBefore + 5);  // the host kept sending frames to the member
  EXPECT_GT(sentBytes, 0);
  EXPECT_EQ(receivedBytes, 0);  // amplification factor 0: not one byte back to the unproven address
  std::uint64_t dropped = 0;
  for (int r = 1; r < static_cast<int>(PathOpenError::Count); ++r) {
    dropped += host->channel().drops(static_cast<PathOpenError>(r));
  }
  EXPECT_EQ(dropped, 100u);
  EXPECT_TRUE(host->channel().pathOpen(id));  // the member's path was not moved
}

}  // namespace
}  // namespace sc::session
