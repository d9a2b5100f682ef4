// ClientEngine's presence (client_engine_presence.cpp) with a fake host: no sockets.
#include "client_engine_fixture.h"

namespace sc::session::test {
namespace {

Presence view(PeerId author) {
  return Presence{author, {1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, false, {}, true};
}

TEST(ClientEnginePresence, SendsWithoutAnAuthorOnlyWhileLive) {
  ClientEngine engine(config("bob"));
  EXPECT_TRUE(engine.sendPresence(view(7)).empty()) << "not live yet";
  joinSession(engine);
  const std::vector<Presence> sentNow = sent<Presence>(engine.sendPresence(view(7)));
  ASSERT_EQ(sentNow.size(), 1u);
  EXPECT_EQ(sentNow[0].author, kNoPeer) << "the host writes the author";
  EXPECT_EQ(sentNow[0].eye, view(7).eye);
  Presence absurd = view(0);
  absurd.eye[0] = 1e300;
  EXPECT_TRUE(engine.sendPresence(absurd).empty()) << "a value the wire refuses is not sent";
}

TEST(ClientEnginePresence, AnotherMembersPresenceIsReportedOwnOrAnonymousIgnored) {
  ClientEngine engine(config("bob"));
  joinSession(engine);
  const ClientActions out = engine.onMessage(message(view(1)), kT0);
  const auto received = actionsOf<client_action::PresenceReceived>(out);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].presence, view(1));
  EXPECT_TRUE(actionsOf<client_action::PresenceReceived>(engine.onMessage(message(view(kSelf)), kT0)).empty());
  EXPECT_TRUE(actionsOf<client_action::PresenceReceived>(engine.onMessage(message(view(kNoPeer)), kT0)).empty());
  EXPECT_EQ(engine.presenceIgnored(), 2u);
  EXPECT_EQ(engine.state(), ClientState::Loading) << "ignored, not a failure";
}

}  // namespace
}  // namespace sc::session::test
