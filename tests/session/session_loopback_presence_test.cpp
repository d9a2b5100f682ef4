// Loopback test of presence (issue 15) over the control channel: a client's Presence reaches the host's own user
// and every other client with the author's id, never its sender; the host's own reaches every client. Real sockets
// on 127.0.0.1. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include <QtTest/QTest>

#include <vector>

namespace sc::session {
namespace {

Presence view(double x) {
  return Presence{kNoPeer, {x, 0.5, 3.0}, {0.0, 0.1, 0.0}, {0.0, 1.0, 0.0}, true, {0.2, 0.3, 0.4}, true};
}

/// Collects every presenceReceived of `source` (SessionHost or SessionClient).
template <typename Source>
std::vector<Presence>& collect(Source& source, std::vector<Presence>& into) {
  QObject::connect(&source, &Source::presenceReceived, &source, [&into](const Presence& p) { into.push_back(p); });
  return into;
}

TEST_F(SessionLoopback, AClientsPresenceReachesTheHostAndTheOtherClient) {
  auto host = startHost();
  auto a = join(*host, QStringLiteral("a"));
  auto b = join(*host, QStringLiteral("b"));
  std::vector<Presence> atHost, atA, atB;
  collect(*host, atHost);
  collect(*a, atA);
  collect(*b, atB);

  ASSERT_TRUE(a->sendPresence(view(1.5)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !atHost.empty() && !atB.empty(); }, kWaitMs));
  Presence expected = view(1.5);
  expected.author = a->peerId();
  EXPECT_EQ(atHost.front(), expected);
  EXPECT_EQ(atB.front(), expected);

  host->setPresence(view(-2.0));  // the host's own user
  ASSERT_TRUE(QTest::qWaitFor([&] { return !atA.empty() && atB.size() >= 2; }, kWaitMs));
  EXPECT_EQ(atA.front().author, kHostPeer);
  EXPECT_EQ(atA.front().eye[0], -2.0);
  EXPECT_EQ(atB.back().author, kHostPeer);
  QTest::qWait(100);
  for (const Presence& p : atA) EXPECT_NE(p.author, a->peerId()) << "never echoed to its sender";
  EXPECT_EQ(host->counters().protocolErrors, 0u);
}

TEST_F(SessionLoopback, AFloodOfPresenceIsThrottledAndAMalformedOneClosesThePeer) {
  auto host = startHost();
  auto watcher = join(*host, QStringLiteral("watcher"));
  std::vector<Presence> atWatcher;
  collect(*watcher, atWatcher);
  RawPeer raw(host->tcpPort());
  ASSERT_TRUE(raw.join(QStringLiteral("raw")).has_value());

  for (int i = 0; i < 200; ++i) raw.send(view(i));  // at once: the burst of 30 passes, the rest is dropped
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return host->counters().presenceRelayed + host->counters().presenceDropped == 200; }, kWaitMs));
  EXPECT_LE(host->counters().presenceRelayed, 40u);
  EXPECT_GE(host->counters().presenceDropped, 160u);
  EXPECT_EQ(host->counters().floodingPeersDropped, 0u);
  EXPECT_EQ(host->peerList().peers.size(), 3u) << "presence over its rate never closes a peer by itself";
  ASSERT_TRUE(QTest::qWaitFor([&] { return atWatcher.size() == host->counters().presenceRelayed; }, kWaitMs));

  // A Presence body with a NaN coordinate: a protocol error like any malformed message.
  QByteArray frame = encodeControlMessage(view(1.0));
  ASSERT_FALSE(frame.isEmpty());
  frame.replace(kControlHeaderSize + 5, 8, QByteArray::fromHex("7ff8000000000000"));
  raw.sendRaw(frame);
  ASSERT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().protocolErrors, 1u);
  EXPECT_EQ(watcher->state(), SessionClient::State::Ready) << "the others stay";
}

}  // namespace
}  // namespace sc::session
