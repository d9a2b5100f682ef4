#include "session/engine/presence_board.h"

#include <iterator>

namespace sc::session {

void PresenceBoard::setPeers(const PeerList& peers, PeerId self) {
  m_members.clear();
  for (const PeerInfo& peer : peers.peers) {
    if (peer.peerId != self) m_members[peer.peerId] = peer.name;
  }
  for (auto it = m_entries.begin(); it != m_entries.end();) {
    const auto member = m_members.find(it->first);
    if (member == m_members.end()) {
      it = m_entries.erase(it);
    } else {
      it->second.name = member->second;
      it = std::next(it);
    }
  }
}

bool PresenceBoard::update(const Presence& presence, Micros now) {
  const auto member = m_members.find(presence.author);
  if (member == m_members.end()) return false;
  m_entries[presence.author] = RemotePresence{presence, member->second, now};
  return true;
}

void PresenceBoard::clear() {
  m_members.clear();
  m_entries.clear();
}

const RemotePresence* PresenceBoard::find(PeerId peer) const {
  const auto it = m_entries.find(peer);
  return it == m_entries.end() ? nullptr : &it->second;
}

std::vector<PeerId> PresenceBoard::dragging() const {
  std::vector<PeerId> ids;
  for (const auto& [id, entry] : m_entries) {
    if (entry.presence.dragging) ids.push_back(id);
  }
  return ids;
}

QString PresenceBoard::nameOf(PeerId peer) const {
  const auto it = m_members.find(peer);
  return it == m_members.end() ? QString() : it->second;
}

}  // namespace sc::session
