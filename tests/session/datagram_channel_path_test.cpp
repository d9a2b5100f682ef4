// Tests the datagram path of src/session/net/host_datagram_channel.cpp and client_datagram_channel.cpp over real UDP
// sockets on 127.0.0.1: the path stays closed until a valid PathOpen, it follows the client to a new address (NAT
// rebinding), a replayed PathOpen moves nothing, and the host drops bad PathOpens by reason. Set-up:
// datagram_session.h.
#include "datagram_session.h"

#include "session/engine/session_clock.h"

#include <gtest/gtest.h>

#include <QtTest/QSignalSpy>

namespace {

using namespace sc::session;
using namespace sc::session::testing;

TEST(DatagramChannel, PathStaysClosedUntilAValidPathOpen) {
  Session s;
  EXPECT_FALSE(s.host.pathOpen(kPeer));
  s.host.sendFrame(1, frameZ(1), sessionNow());
  EXPECT_EQ(s.host.traffic(kPeer).datagramsSent, 0u);  // nowhere to send yet
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  ASSERT_TRUE(s.open());
  ASSERT_EQ(opened.count(), 1);
  EXPECT_EQ(opened.at(0).at(0).value<PeerId>(), kPeer);
  EXPECT_EQ(s.host.peerPort(kPeer), s.client.localPort());
  EXPECT_EQ(s.host.drops(PathOpenError::None), 1u);
  EXPECT_GE(s.client.pathOpensSent(), 1u);
}

/// Rebinds the client's socket to another local port while its channel stays open (NAT rebinding: the same
/// client, its PathOpen count going on, now seen from a new port). Returns the new port (0 on failure).
quint16 rebind(ClientDatagramChannel& client) {
  const quint16 old = client.localPort();
  for (int attempt = 0; attempt < 8; ++attempt) {
    if (!client.bind(kLoopback, nullptr)) return 0;
    if (client.localPort() != old) return client.localPort();
  }
  return 0;
}

TEST(DatagramChannel, PathFollowsTheClientToANewAddress) {
  Session s;
  ASSERT_TRUE(s.open());
  const quint16 before = s.client.localPort();
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  const quint16 after = rebind(s.client);
  ASSERT_NE(after, 0);
  ASSERT_NE(after, before);
  // The client's next PathOpen (a higher sequence) moves the path.
  ASSERT_TRUE(waitUntil([&] { return s.host.peerPort(kPeer) == after; }));
  EXPECT_EQ(opened.count(), 1);
  EXPECT_EQ(s.host.drops(PathOpenError::Replayed), 0u);
  s.host.sendFrame(1, frameZ(1), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }));
  s.client.close();
  EXPECT_EQ(s.client.pathOpenIntervalMs(), 0);  // closed
  s.host.removePeer(kPeer);
  EXPECT_FALSE(s.host.pathOpen(kPeer));
}

TEST(DatagramChannel, ReplayedPathOpenDoesNotMoveThePath) {
  Session s;
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::None) >= 1; }));
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  // What an eavesdropper recorded: the client's first PathOpen (encoding is deterministic, so these are its exact
  // bytes) and the latest one the host accepted (on loopback every one is accepted, in order).
  const auto peer = static_cast<std::uint16_t>(kPeer);
  const QByteArray first = encodePathOpen(peer, kToken, 1, kKey);
  const auto latestSequence = static_cast<std::uint32_t>(s.host.drops(PathOpenError::None));
  const QByteArray latest = encodePathOpen(peer, kToken, latestSequence, kKey);

  Stranger attacker;
  attacker.send(first, s.host.port());
  attacker.send(latest, s.host.port());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::Replayed) == 2; }));
  EXPECT_EQ(opened.count(), 0);
  EXPECT_EQ(s.host.peerAddress(kPeer), kLoopback);
  EXPECT_EQ(s.host.peerPort(kPeer), s.client.localPort());  // the path stayed with the client

  // NAT rebinding still works: the client's next (fresh) PathOpen from a new port moves the path. (Before any
  // frame, so the client still sends every kPathOpenIntervalMs.)
  const quint16 after = rebind(s.client);
  ASSERT_NE(after, 0);
  ASSERT_TRUE(waitUntil([&] { return s.host.peerPort(kPeer) == after; }));
  EXPECT_EQ(opened.count(), 1);
  EXPECT_EQ(s.host.drops(PathOpenError::Replayed), 2u);

  // The attacker replays again, now from its socket to the moved path: still nothing moves. Frames go to the
  // client, none to the attacker.
  attacker.send(latest, s.host.port());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::Replayed) == 3; }));
  EXPECT_EQ(s.host.peerPort(kPeer), after);
  s.host.sendFrame(1, frameZ(1), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }));
  EXPECT_FALSE(attacker.socket.hasPendingDatagrams());
  EXPECT_EQ(opened.count(), 1);
}

TEST(DatagramChannel, HostDropsBadPathOpensByReason) {
  HostDatagramChannel host;
  ASSERT_TRUE(host.bind(kLoopback, 0, nullptr));
  host.addPeer(kPeer, kKey, kToken);
  Stranger stranger;
  const std::uint16_t peer = static_cast<std::uint16_t>(kPeer);
  const QByteArray valid = encodePathOpen(peer, kToken, 5, kKey);
  std::mt19937 rng(11);
  QByteArray random(kPathOpenSize + 20, '\0');
  for (char& c : random) c = static_cast<char>(rng());
  QByteArray forged = valid;  // right length and peer id, random rest
  for (int i = 6; i < forged.size(); ++i) forged[i] = static_cast<char>(rng());
  const auto totalDrops = [&] {
    std::uint64_t total = 0;
    for (int r = 0; r < static_cast<int>(PathOpenError::Count); ++r) total += host.drops(static_cast<PathOpenError>(r));
    return total;
  };

  stranger.send(random, host.port());                                                           // Truncated (length)
  stranger.send(valid.left(kPathOpenSize - 1), host.port());                                    // Truncated
  stranger.send(encodePathOpen(peer, bytesOf('w', kPathTokenSize), 5, kKey), host.port());      // Stranger (token)
  stranger.send(encodePathOpen(99, kToken, 5, kKey), host.port());                              // Stranger (peer)
  stranger.send(encodePathOpen(peer, kToken, 5, bytesOf('x', kDatagramKeySize)), host.port());  // BadTag
  stranger.send(forged, host.port());                                                           // BadTag
  stranger.send(encodePathOpen(peer, kToken, 0, kKey), host.port());  // Replayed (0 is never above the highest)
  ASSERT_TRUE(waitUntil([&] { return totalDrops() == 7; }));
  EXPECT_EQ(host.drops(PathOpenError::Truncated), 2u);
  EXPECT_EQ(host.drops(PathOpenError::Stranger), 2u);
  EXPECT_EQ(host.drops(PathOpenError::BadTag), 2u);
  EXPECT_EQ(host.drops(PathOpenError::Replayed), 1u);
  EXPECT_EQ(host.drops(PathOpenError::None), 0u);
  EXPECT_FALSE(host.pathOpen(kPeer));

  // Sequences need not be consecutive, only increasing: 5 opens; 5 again and 3 are replays; 6 is fresh.
  QSignalSpy opened(&host, &HostDatagramChannel::pathOpened);
  stranger.send(valid, host.port());
  stranger.send(valid, host.port());
  stranger.send(encodePathOpen(peer, kToken, 3, kKey), host.port());
  stranger.send(encodePathOpen(peer, kToken, 6, kKey), host.port());
  ASSERT_TRUE(waitUntil([&] { return totalDrops() == 11; }));
  EXPECT_EQ(host.drops(PathOpenError::None), 2u);
  EXPECT_EQ(host.drops(PathOpenError::Replayed), 3u);
  EXPECT_FALSE(host.pathOpen(kPeer)) << "accepted, but not validated before the challenge is answered";
  ASSERT_TRUE(stranger.answerChallenge(host.port()));
  ASSERT_TRUE(waitUntil([&] { return host.pathOpen(kPeer); }));
  EXPECT_EQ(host.peerPort(kPeer), stranger.socket.localPort());
  EXPECT_EQ(opened.count(), 1);  // the same address twice: one signal

  // Re-adding the peer (a new Welcome) forgets its highest sequence: the client starts again at 1.
  host.addPeer(kPeer, kKey, kToken);
  EXPECT_FALSE(host.pathOpen(kPeer));
  stranger.send(encodePathOpen(peer, kToken, 1, kKey), host.port());
  ASSERT_TRUE(waitUntil([&] { return host.drops(PathOpenError::None) == 3; }));
  ASSERT_TRUE(stranger.answerChallenge(host.port()));
  ASSERT_TRUE(waitUntil([&] { return host.pathOpen(kPeer); }));
  EXPECT_EQ(host.drops(PathOpenError::Replayed), 3u);

  // A removed peer's PathOpen is a stranger's.
  host.removePeer(kPeer);
  stranger.send(encodePathOpen(peer, kToken, 2, kKey), host.port());
  ASSERT_TRUE(waitUntil([&] { return host.drops(PathOpenError::Stranger) == 3; }));
  EXPECT_FALSE(host.pathOpen(kPeer));
}

}  // namespace
