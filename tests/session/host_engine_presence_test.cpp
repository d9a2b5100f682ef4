// HostEngine's presence relay (host_engine_presence.cpp) on a fake clock: no sockets.
#include "host_engine_fixture.h"

namespace sc::session::testing {
namespace {

Presence viewFrom(double x, bool dragging = false) {
  return Presence{kNoPeer, {x, 1.0, 4.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, true, {0.1, 0.2, 0.9}, dragging};
}

using HostEnginePresence = HostEngineTest;

TEST_F(HostEnginePresence, AClientsPresenceIsRelayedToTheOthersWithItsId) {
  startEngine();
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  const PeerId carol = join(QStringLiteral("carol"));
  Presence sent = viewFrom(2.0, true);
  sent.author = 77;  // a forged author is overwritten
  const HostActions actions = engine().onMessage(bob, sent, now());
  Presence expected = sent;
  expected.author = bob;
  for (PeerId other : {alice, carol}) {
    const auto relayed = sentTo<Presence>(actions, other);
    ASSERT_EQ(relayed.size(), 1u) << other;
    EXPECT_EQ(relayed[0], expected);
  }
  EXPECT_TRUE(sentTo<Presence>(actions, bob).empty()) << "never echoed to its author";
  EXPECT_TRUE(sentToAll<Presence>(actions).empty());
  const auto reported = actionsOf<PresenceReceived>(actions);
  ASSERT_EQ(reported.size(), 1u) << "the host's own user sees it too";
  EXPECT_EQ(reported[0].presence, expected);
  EXPECT_EQ(engine().counters().presenceRelayed, 1u);
  EXPECT_TRUE(actionsOf<ClosePeer>(actions).empty());
}

TEST_F(HostEnginePresence, OverTheRateIsDroppedAndCountedNeverClosed) {
  HostEngineOptions options;
  options.presenceRate = RateLimit{30.0, 30.0};
  startEngine(options);
  const PeerId alice = join(QStringLiteral("alice"));
  const PeerId bob = join(QStringLiteral("bob"));
  std::size_t relayed = 0;
  for (int i = 0; i < 100; ++i) {  // 100 at once: the burst of 30 passes
    const HostActions actions = engine().onMessage(alice, viewFrom(i), now());
    relayed += sentTo<Presence>(actions, bob).size();
    EXPECT_TRUE(actionsOf<ClosePeer>(actions).empty());
  }
  EXPECT_EQ(relayed, 30u);
  EXPECT_EQ(engine().counters().presenceDropped, 70u);
  EXPECT_EQ(engine().counters().floodingPeersDropped, 0u);
  advance(100ms);  // 3 more tokens
  for (int i = 0; i < 5; ++i) relayed += sentTo<Presence>(engine().onMessage(alice, viewFrom(i), now()), bob).size();
  EXPECT_EQ(relayed, 33u);
  EXPECT_EQ(engine().counters().presenceDropped, 72u);
  EXPECT_EQ(engine().peerList().peers.size(), 3u) << "alice is still a member";
}

TEST_F(HostEnginePresence, TheHostsOwnPresenceGoesToEveryMember) {
  startEngine();
  join(QStringLiteral("alice"));
  const HostActions actions = engine().setLocalPresence(viewFrom(3.0), now());
  const auto sent = sentToAll<Presence>(actions);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].author, kHostPeer);
  EXPECT_EQ(sent[0].eye[0], 3.0);
  Presence absurd = viewFrom(std::numeric_limits<double>::infinity());
  EXPECT_TRUE(engine().setLocalPresence(absurd, now()).list.empty()) << "a value the wire refuses is not sent";
}

}  // namespace
}  // namespace sc::session::testing
