#pragma once
// The constraint sets of everybody holding an edit lease (issue 15, "several people drag at once") and the one set
// the host's deformer solves: their union. Each holder's handle groups keep their order and sit together in the
// union, holders in the order their sets came in; anchors are merged (an anchor two people hold is held once).
//
// Two people's sets conflict when one's handle vertices are the other's handle or anchor vertices (one would move
// what the other moves or holds); shared anchors do not conflict. A conflicting set is refused, never merged.
// Pure data, no Qt, no clock. Cost: check() and combined() O(total ids · log); the rest O(holders).

#include "session/wire/lock_messages.h"
#include "spectral/spectral_deformer.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace sc::session {

/// Where one holder's handle groups sit in the union: groups [first, first + count).
struct GroupRange {
  std::size_t first = 0;
  std::size_t count = 0;
  friend bool operator==(const GroupRange&, const GroupRange&) = default;
};

class SharedConstraints {
 public:
  /// The holders whose sets `set` from `peer` would conflict with (empty: none), in their order. `peer`'s own
  /// current set is not counted (it is about to be replaced).
  [[nodiscard]] std::vector<PeerId> conflicts(PeerId peer, const spectral::ConstraintSet& set) const;
  /// The number of constrained ids of the union if `peer`'s set became `set` (what the factorisation costs).
  [[nodiscard]] std::size_t idsWith(PeerId peer, const spectral::ConstraintSet& set) const;
  /// Puts `peer`'s set in (replacing its previous one in place, else after the others). Bumps version().
  void set(PeerId peer, spectral::ConstraintSet set);
  /// Takes `peer`'s set out; false (and no change) when it had none. Bumps version() when it had one.
  bool remove(PeerId peer);
  /// The union (see the header comment).
  [[nodiscard]] spectral::ConstraintSet combined() const;
  /// `peer`'s groups in combined(); nullopt when it has no set.
  [[nodiscard]] std::optional<GroupRange> groups(PeerId peer) const;
  /// Every holder's poses (its own groups, in its order; missing ones at identity) laid out as combined()'s groups.
  /// `posesOf(peer)` returns the holder's poses (fewer than its groups: the rest at identity; more: ignored).
  template <typename PosesOf>
  [[nodiscard]] std::vector<spectral::HandleTransform> layout(PosesOf&& posesOf) const {
    std::vector<spectral::HandleTransform> out;
    for (const Member& member : m_members) {
      const std::span<const spectral::HandleTransform> poses = posesOf(member.peer);
      for (std::size_t g = 0; g < member.set.handles.size(); ++g) {
        out.push_back(g < poses.size() ? poses[g] : spectral::HandleTransform{});
      }
    }
    return out;
  }
  /// The holders with a set, in union order.
  [[nodiscard]] std::vector<PeerId> holders() const;
  /// Changes with every set() and effective remove(): a factorisation prepared at one version is current only while
  /// it is unchanged.
  [[nodiscard]] std::uint64_t version() const { return m_version; }

 private:
  struct Member {
    PeerId peer = kNoPeer;
    spectral::ConstraintSet set;
  };
  std::vector<Member> m_members;
  std::uint64_t m_version = 0;
};

}  // namespace sc::session
