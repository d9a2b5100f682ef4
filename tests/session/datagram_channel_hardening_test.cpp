// Issue 14 ("Hardening II"), datagram items, over real UDP sockets on 127.0.0.1 (host_datagram_channel.cpp,
// client_datagram_channel.cpp): a datagram replayed after the 16-bit sequence wrapped does not freeze the client
// (item 5); a PathOpen from a new address does not move the stream before that address echoes the host's
// challenge, and until then the host sends it at most the bytes it received from it, and a wrong echo moves nothing
// (item 6); each channel reads a
// bounded number of datagrams per event-loop pass (item 11). Set-up: datagram_session.h.
#include "datagram_session.h"

#include "session/engine/session_clock.h"
#include "session/wire/coefficient_codec.h"

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>
#include <QtNetwork/QNetworkDatagram>
#include <QtTest/QSignalSpy>

#include <cstdint>

namespace {

using namespace sc::session;
using namespace sc::session::testing;

/// Reads every datagram pending on `socket`; returns their total size in bytes.
std::uint64_t drain(QUdpSocket& socket) {
  std::uint64_t bytes = 0;
  while (socket.hasPendingDatagrams()) bytes += static_cast<std::uint64_t>(socket.receiveDatagram().data().size());
  return bytes;
}

TEST(DatagramHardening, ReplayAfterSequenceWrapKeepsFramesFlowing) {
  Session s;
  ASSERT_TRUE(s.open());
  // A datagram of this client's stream at sequence 200 (frame 100), as an eavesdropper would have recorded it.
  CoefficientEncoder recorder(kKey, static_cast<std::uint16_t>(kPeer));
  QByteArray recorded;
  for (std::uint32_t f = 0; f <= 100; ++f) recorded = recorder.encodeFrame(f, frameZ(f)).front();
  // The host streams past the 16-bit wrap: 32,800 frames of 2 datagrams, every one read by the client.
  constexpr int kFrames = 32800;
  ASSERT_TRUE(s.stream(1, kFrames, 200));
  ASSERT_EQ(s.client.framesApplied(), static_cast<std::uint64_t>(kFrames));
  const std::uint64_t droppedBefore = s.client.droppedDatagrams();

  Stranger attacker;
  attacker.send(recorded, s.client.localPort());  // its 16-bit number reads as ~190 ahead of the newest
  ASSERT_TRUE(waitUntil([&] { return s.client.droppedDatagrams() > droppedBefore; }));

  // Genuine frames after the replay are applied: the stream does not freeze.
  ASSERT_TRUE(s.stream(kFrames + 1, 50, 25));
  EXPECT_EQ(s.client.framesApplied(), static_cast<std::uint64_t>(kFrames + 50));
  EXPECT_EQ(s.client.receivedFrame(), static_cast<std::uint32_t>(kFrames + 50));
}

TEST(DatagramHardening, NewPathIsUsedOnlyAfterItEchoesTheChallenge) {
  Session s;
  ASSERT_TRUE(s.open());
  const quint16 clientPort = s.client.localPort();
  // A member points its stream at a victim: a valid, fresh PathOpen (it knows its key and token) whose source is
  // the victim's address, here a second socket.
  Stranger victim;
  const auto peer = static_cast<std::uint16_t>(kPeer);
  const std::uint64_t acceptedBefore = s.host.drops(PathOpenError::None);
  constexpr int kOpens = 3;
  for (int i = 0; i < kOpens; ++i) victim.send(encodePathOpen(peer, kToken, 1000000 + i, kKey), s.host.port());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::None) == acceptedBefore + kOpens; }));

  // The stream stays on the validated path; the victim gets no frame, at most the bytes it "sent".
  EXPECT_EQ(s.host.peerPort(kPeer), clientPort);
  const std::uint64_t clientBefore = s.client.assembler()->accepted();
  for (std::uint32_t f = 1; f <= 20; ++f) s.host.sendFrame(f, frameZ(f), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == clientBefore + 40; }));
  waitUntil([] { return false; }, 50);  // anything sent to the victim has arrived
  const std::uint64_t victimBytes = drain(victim.socket);
  EXPECT_LE(victimBytes, static_cast<std::uint64_t>(kOpens * kPathOpenSize));
  EXPECT_GE(victimBytes, static_cast<std::uint64_t>(kPathProbeSize)) << "the challenges were sent";
  EXPECT_EQ(s.host.peerPort(kPeer), clientPort);

  // An address that does receive (it echoes the challenge) gets the stream: the path moves.
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  victim.send(encodePathOpen(peer, kToken, 2000000, kKey), s.host.port());
  ASSERT_TRUE(victim.answerChallenge(s.host.port()));
  ASSERT_TRUE(waitUntil([&] { return s.host.peerPort(kPeer) == victim.socket.localPort(); }));
  EXPECT_EQ(opened.count(), 1);
  s.host.sendFrame(21, frameZ(21), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return victim.socket.hasPendingDatagrams(); }));
  waitUntil([] { return false; }, 50);
  EXPECT_EQ(drain(victim.socket), 2u * 378u) << "one frame, 2 datagrams of 378 bytes";
}

TEST(DatagramHardening, ChallengeWithAWrongValueOrFromElsewhereDoesNotMoveThePath) {
  Session s;
  ASSERT_TRUE(s.open());
  Stranger candidate, elsewhere;
  const auto peer = static_cast<std::uint16_t>(kPeer);
  candidate.send(encodePathOpen(peer, kToken, 1000000, kKey), s.host.port());
  ASSERT_TRUE(waitUntil([&] { return candidate.socket.hasPendingDatagrams(); }));
  const DatagramMac mac(kKey);
  const PathProbeResult challenge =
      decodePathProbe(candidate.socket.receiveDatagram().data(), MessageType::PathChallenge, mac);
  ASSERT_EQ(challenge.error, PathOpenError::None);
  // A guessed value from the candidate, and the right value from another address: neither validates.
  candidate.send(encodePathProbe(MessageType::PathResponse, peer, challenge.challenge + 1, mac), s.host.port());
  elsewhere.send(encodePathProbe(MessageType::PathResponse, peer, challenge.challenge, mac), s.host.port());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::WrongChallenge) == 2; }));
  EXPECT_EQ(s.host.peerPort(kPeer), s.client.localPort());
}

/// Sends 4 × bound short datagrams to `port`, then runs one event-loop pass at a time until the receiver has read
/// some; `read` counts what it read. Returns the count after that first pass, and waits until all were read.
std::uint64_t readInFirstPass(quint16 port, int bound, const std::function<std::uint64_t()>& read) {
  Stranger flood;
  const int total = 4 * bound;
  const std::uint64_t before = read();
  for (int i = 0; i < total; ++i) flood.send(QByteArray(10, 'x'), port);
  for (int pass = 0; pass < 1000 && read() == before; ++pass) QCoreApplication::processEvents();
  const std::uint64_t first = read() - before;
  EXPECT_TRUE(waitUntil([&] { return read() - before == static_cast<std::uint64_t>(total); }))
      << "the rest is read in later passes";
  return first;
}

constexpr int kBound = HostDatagramChannel::kMaxDatagramsPerPass;
static_assert(ClientDatagramChannel::kMaxDatagramsPerPass == kBound);

TEST(DatagramHardening, HostReadsABoundedNumberOfDatagramsPerEventLoopPass) {
  HostDatagramChannel host;
  ASSERT_TRUE(host.bind(kLoopback, 0, nullptr));
  const std::uint64_t first =
      readInFirstPass(host.port(), kBound, [&] { return host.drops(PathOpenError::Truncated); });
  EXPECT_GE(first, 1u);
  EXPECT_LE(first, static_cast<std::uint64_t>(kBound));
}

TEST(DatagramHardening, ClientReadsABoundedNumberOfDatagramsPerEventLoopPass) {
  ClientDatagramChannel client;
  ASSERT_TRUE(client.bind(kLoopback, nullptr));
  const std::uint64_t first = readInFirstPass(client.localPort(), kBound, [&] { return client.datagramsRead(); });
  EXPECT_GE(first, 1u);
  EXPECT_LE(first, static_cast<std::uint64_t>(kBound));
}

}  // namespace
