#pragma once
// PresenceBoard: the latest Presence of every other member (issue 15), socket-free: per peer id its camera,
// pointer, dragging flag and when it arrived. Only members of the latest PeerList other than this user are kept:
// setPeers() removes those who left, and update() ignores unknown authors, so a host cannot make it grow beyond
// the PeerList (≤ kMaxPeers entries). Cost: O(log peers) per update, O(peers) per setPeers().

#include "session/engine/receiver_statistics.h"
#include "session/wire/control_messages.h"

#include <map>
#include <vector>

namespace sc::session {

struct RemotePresence {
  Presence presence;     ///< author = the peer's id
  QString name;          ///< from the PeerList
  Micros receivedAt{0};  ///< the clock when it arrived
};

class PresenceBoard {
 public:
  /// The session's members now, and this user's id (never on the board). Entries of peers not listed are removed.
  void setPeers(const PeerList& peers, PeerId self);
  /// Stores `presence` (replacing the author's previous one); false (ignored) when the author is not a listed
  /// member other than this user.
  bool update(const Presence& presence, Micros now);
  /// Removes everything (no session).
  void clear();

  [[nodiscard]] const std::map<PeerId, RemotePresence>& entries() const { return m_entries; }
  [[nodiscard]] const RemotePresence* find(PeerId peer) const;
  /// Members whose latest presence says they drag, ascending ids.
  [[nodiscard]] std::vector<PeerId> dragging() const;
  /// The listed member's name ("" when unknown).
  [[nodiscard]] QString nameOf(PeerId peer) const;

 private:
  std::map<PeerId, QString> m_members;  ///< the latest PeerList without this user
  std::map<PeerId, RemotePresence> m_entries;
};

}  // namespace sc::session
