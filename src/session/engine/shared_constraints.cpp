#include "session/engine/shared_constraints.h"

#include <algorithm>

namespace sc::session {
namespace {

std::vector<int> sorted(std::vector<int> ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<int> handleIds(const spectral::ConstraintSet& set) {
  std::vector<int> ids;
  for (const spectral::HandleGroup& group : set.handles)
    ids.insert(ids.end(), group.vertices.begin(), group.vertices.end());
  return sorted(std::move(ids));
}

bool intersect(const std::vector<int>& a, const std::vector<int>& b) {  // both sorted
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (*i == *j) return true;
    if (*i < *j) {
      ++i;
    } else {
      ++j;
    }
  }
  return false;
}

std::size_t idCount(const spectral::ConstraintSet& set) {
  std::size_t count = set.anchors.size();
  for (const spectral::HandleGroup& group : set.handles) count += group.vertices.size();
  return count;
}

}  // namespace

std::vector<PeerId> SharedConstraints::conflicts(PeerId peer, const spectral::ConstraintSet& set) const {
  const std::vector<int> handles = handleIds(set);
  const std::vector<int> anchors = sorted(set.anchors);
  std::vector<PeerId> out;
  for (const Member& member : m_members) {
    if (member.peer == peer) continue;
    const std::vector<int> theirHandles = handleIds(member.set);
    const std::vector<int> theirAnchors = sorted(member.set.anchors);
    if (intersect(handles, theirHandles) || intersect(handles, theirAnchors) || intersect(anchors, theirHandles)) {
      out.push_back(member.peer);
    }
  }
  return out;
}

std::size_t SharedConstraints::idsWith(PeerId peer, const spectral::ConstraintSet& set) const {
  std::size_t count = idCount(set);
  for (const Member& member : m_members) {
    if (member.peer != peer) count += idCount(member.set);
  }
  return count;
}

void SharedConstraints::set(PeerId peer, spectral::ConstraintSet set) {
  ++m_version;
  const auto it = std::find_if(m_members.begin(), m_members.end(), [peer](const Member& m) { return m.peer == peer; });
  if (it != m_members.end()) {
    it->set = std::move(set);
  } else {
    m_members.push_back({peer, std::move(set)});
  }
}

bool SharedConstraints::remove(PeerId peer) {
  const auto it = std::find_if(m_members.begin(), m_members.end(), [peer](const Member& m) { return m.peer == peer; });
  if (it == m_members.end()) return false;
  m_members.erase(it);
  ++m_version;
  return true;
}

spectral::ConstraintSet SharedConstraints::combined() const {
  spectral::ConstraintSet out;
  std::vector<int> anchors;
  for (const Member& member : m_members) {
    out.handles.insert(out.handles.end(), member.set.handles.begin(), member.set.handles.end());
    anchors.insert(anchors.end(), member.set.anchors.begin(), member.set.anchors.end());
  }
  out.anchors = m_members.size() == 1 ? m_members.front().set.anchors : sorted(std::move(anchors));
  return out;
}

std::optional<GroupRange> SharedConstraints::groups(PeerId peer) const {
  std::size_t first = 0;
  for (const Member& member : m_members) {
    if (member.peer == peer) return GroupRange{first, member.set.handles.size()};
    first += member.set.handles.size();
  }
  return std::nullopt;
}

std::vector<PeerId> SharedConstraints::holders() const {
  std::vector<PeerId> out;
  for (const Member& member : m_members) out.push_back(member.peer);
  return out;
}

}  // namespace sc::session
