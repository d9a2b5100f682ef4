// ClientEngine, presence (issue 15): this user's Presence to the host, the other members' from it. O(1) each.
#include "session/engine/client_engine.h"

namespace sc::session {

ClientActions ClientEngine::sendPresence(Presence presence) {
  ClientActions out;
  presence.author = kNoPeer;  // the host writes ours
  if (live()) send(presence, out);
  return out;
}

void ClientEngine::onPresence(const Presence& presence, ClientActions& out) {
  if (presence.author == kNoPeer || (m_session && presence.author == m_session->peerId)) {
    ++m_presenceIgnored;  // a host that echoes or forgets the author: nothing to show
    return;
  }
  out.emplace_back(client_action::PresenceReceived{presence});
}

}  // namespace sc::session
