// HostEngine, presence (issue 15): members' Presence relayed to the others with the author's id, the host's own
// user's presence sent to every member. Cost: O(peers) per message; nothing stored per message.
#include "session/engine/host_engine.h"

namespace sc::session {

void HostEngine::relayPresence(Peer& peer, Presence presence, Micros now, HostActions& out) {
  if (!peer.presence.take(now)) {
    ++m_counters.presenceDropped;  // a view update is superseded by the next one: dropping it loses nothing lasting
    return;
  }
  ++m_counters.presenceRelayed;
  presence.author = peer.id;  // whatever the sender wrote
  for (const auto& [id, other] : m_peers) {
    if (id != peer.id && other.member()) out.add(SendToPeer{id, presence});
  }
  out.add(PresenceReceived{std::move(presence)});
}

HostActions HostEngine::setLocalPresence(const Presence& presence, Micros /*now*/) {
  HostActions out;
  if (!m_started || m_shutDown) return finish(std::move(out));
  Presence own = presence;
  own.author = kHostPeer;
  if (encodeControlMessage(own).isEmpty()) return finish(std::move(out));  // non-finite or out of bounds
  out.add(SendToAll{std::move(own)});
  return finish(std::move(out));
}

}  // namespace sc::session
