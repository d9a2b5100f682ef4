#include "session/engine/lock_arbiter.h"

#include <algorithm>
#include <cassert>

namespace sc::session {

namespace {

LockEvent toAll(const LockNotice& notice) { return LockEvent{LockAudience::AllPeers, kNoPeer, notice}; }

LockEvent toPeer(PeerId peer, const LockNotice& notice) { return LockEvent{LockAudience::OnePeer, peer, notice}; }

}  // namespace

LockArbiter::LockArbiter(Millis lease, Millis maxHoldWhileWaited, int maxHolders)
    : m_lease(lease), m_maxHoldWhileWaited(maxHoldWhileWaited), m_maxHolders(std::max(1, maxHolders)) {
  assert(lease.count() > 0 && "the lease must be positive");
}

LockEvents LockArbiter::handleMessage(PeerId peer, const LockMessage& message, Millis now) {
  assert(peer != kNoPeer && "peer id 0 is reserved");
  switch (message.kind) {
    case LockRequestKind::Request:
      return handleRequest(peer, now);
    case LockRequestKind::Release:
      return handleRelease(peer, message.epoch, now);
    case LockRequestKind::Renew:
      return handleRenew(peer, message.epoch, now);
  }
  return ignore();  // an undecoded kind: dropped and counted
}

std::optional<std::size_t> LockArbiter::indexOf(PeerId peer) const {
  const auto it = std::find_if(m_holders.begin(), m_holders.end(), [peer](const Holder& h) { return h.peer == peer; });
  if (it == m_holders.end()) return std::nullopt;
  return static_cast<std::size_t>(it - m_holders.begin());
}

std::vector<LockHolding> LockArbiter::holders() const {
  std::vector<LockHolding> out;
  out.reserve(m_holders.size());
  for (const Holder& h : m_holders) out.push_back({h.peer, h.epoch});
  return out;
}

LockEpoch LockArbiter::epochOf(PeerId peer) const {
  const std::optional<std::size_t> index = indexOf(peer);
  return index ? m_holders[*index].epoch : kNoEpoch;
}

LockEvents LockArbiter::handleRequest(PeerId peer, Millis now) {
  LockEvents events;
  if (const std::optional<std::size_t> index = indexOf(peer)) {
    // Idempotent: the holder asks again (e.g. it lost our Granted); repeat it to the holder only.
    Holder& holder = m_holders[*index];
    holder.lastHeard = now;
    events.push_back(toPeer(peer, LockNotice{LockNoticeKind::Granted, peer, holder.epoch}));
  } else if (static_cast<int>(m_holders.size()) < m_maxHolders && m_queue.empty()) {
    grant(peer, now, events);
  } else {
    if (std::find(m_queue.begin(), m_queue.end(), peer) == m_queue.end()) {
      if (m_queue.empty()) m_waitingSince = now;
      m_queue.push_back(peer);
    }
    events.push_back(queuedNotice(peer));
  }
  return events;
}

LockEvents LockArbiter::handleRelease(PeerId peer, LockEpoch epoch, Millis now) {
  const std::optional<std::size_t> index = indexOf(peer);
  if (index && (epoch == kNoEpoch || epoch == m_holders[*index].epoch)) {
    return endTenure(*index, LockReleaseReason::Released, now);
  }
  if (epoch == kNoEpoch && removeFromQueue(peer)) {
    return {toPeer(peer, LockNotice{LockNoticeKind::Dequeued, peer})};
  }
  return ignore();  // release of a tenure the peer does not hold, or a cancel with nothing to cancel
}

LockEvents LockArbiter::handleRenew(PeerId peer, LockEpoch epoch, Millis now) {
  const std::optional<std::size_t> index = indexOf(peer);
  if (!index || m_holders[*index].epoch != epoch) {
    return ignore();
  }
  m_holders[*index].lastHeard = now;
  return {};
}

LockEvents LockArbiter::peerDisconnected(PeerId peer, Millis now) {
  if (const std::optional<std::size_t> index = indexOf(peer)) {
    return endTenure(*index, LockReleaseReason::Disconnected, now);
  }
  removeFromQueue(peer);  // nobody to notify: the peer is gone and positions are only told on request
  return {};
}

LockEvents LockArbiter::revokeByHost(Millis now, PeerId peer) {
  std::vector<PeerId> revoked;
  for (const Holder& h : m_holders) {
    if (peer == kNoPeer || h.peer == peer) revoked.push_back(h.peer);
  }
  LockEvents events;
  for (const PeerId p : revoked) {  // the queue's heads granted meanwhile keep their new leases
    const std::optional<std::size_t> index = indexOf(p);
    if (!index) continue;
    LockEvents ended = endTenure(*index, LockReleaseReason::RevokedByHost, now);
    events.insert(events.end(), ended.begin(), ended.end());
  }
  return events;
}

LockEvents LockArbiter::tick(Millis now) {
  LockEvents events;
  for (std::size_t i = 0; i < m_holders.size();) {
    if (now - m_holders[i].lastHeard > m_lease) {
      LockEvents ended = endTenure(i, LockReleaseReason::LeaseExpired, now);
      events.insert(events.end(), ended.begin(), ended.end());
    } else {
      ++i;
    }
  }
  if (!m_holders.empty() && !m_queue.empty() && m_maxHoldWhileWaited.count() > 0 &&
      now - std::max(m_holders.front().grantedAt, m_waitingSince) > m_maxHoldWhileWaited) {
    ++m_revokedForWaiters;  // the longest-held lease makes room
    LockEvents ended = endTenure(0, LockReleaseReason::LeaseExpired, now);
    events.insert(events.end(), ended.begin(), ended.end());
  }
  return events;
}

DragVerdict LockArbiter::acceptDrag(PeerId peer, LockEpoch epoch, Millis now) {
  const std::optional<std::size_t> index = indexOf(peer);
  if (!index) {
    return DragVerdict::NotHolder;
  }
  if (epoch != m_holders[*index].epoch) {
    return DragVerdict::StaleEpoch;
  }
  m_holders[*index].lastHeard = now;
  return DragVerdict::Accepted;
}

std::optional<Millis> LockArbiter::leaseDeadline() const {
  if (m_holders.empty()) {
    return std::nullopt;
  }
  Millis earliest = m_holders.front().lastHeard;
  for (const Holder& h : m_holders) earliest = std::min(earliest, h.lastHeard);
  return earliest + m_lease;
}

LockEvents LockArbiter::endTenure(std::size_t index, LockReleaseReason reason, Millis now) {
  assert(index < m_holders.size() && "endTenure needs a holder");
  const Holder ended = m_holders[index];
  LockEvents events{toAll(LockNotice{LockNoticeKind::Released, ended.peer, ended.epoch, 0, reason})};
  m_holders.erase(m_holders.begin() + static_cast<std::ptrdiff_t>(index));
  if (!m_queue.empty()) {
    const PeerId next = m_queue.front();
    m_queue.pop_front();
    if (!m_queue.empty()) m_waitingSince = now;  // the rest wait on from here for the next lease
    grant(next, now, events);
  }
  return events;
}

void LockArbiter::grant(PeerId peer, Millis now, LockEvents& events) {
  assert(static_cast<int>(m_holders.size()) < m_maxHolders && !indexOf(peer) && "never grant twice");
  m_holders.push_back(Holder{peer, ++m_lastEpoch, now, now});
  events.push_back(toAll(LockNotice{LockNoticeKind::Granted, peer, m_holders.back().epoch}));
}

bool LockArbiter::removeFromQueue(PeerId peer) {
  const auto it = std::find(m_queue.begin(), m_queue.end(), peer);
  if (it == m_queue.end()) {
    return false;
  }
  m_queue.erase(it);
  return true;
}

LockEvent LockArbiter::queuedNotice(PeerId peer) const {
  const auto it = std::find(m_queue.begin(), m_queue.end(), peer);
  assert(it != m_queue.end() && "queuedNotice for a queued peer only");
  const auto position = static_cast<std::uint32_t>(it - m_queue.begin()) + 1;
  return toPeer(peer, LockNotice{LockNoticeKind::Queued, peer, kNoEpoch, position});
}

LockEvents LockArbiter::ignore() {
  ++m_ignored;
  return {};
}

}  // namespace sc::session
