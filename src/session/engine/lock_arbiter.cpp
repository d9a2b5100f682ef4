#include "session/engine/lock_arbiter.h"

#include <algorithm>
#include <cassert>

namespace sc::session {

namespace {

LockEvent toAll(const LockNotice& notice) { return LockEvent{LockAudience::AllPeers, kNoPeer, notice}; }

LockEvent toPeer(PeerId peer, const LockNotice& notice) { return LockEvent{LockAudience::OnePeer, peer, notice}; }

}  // namespace

LockArbiter::LockArbiter(Millis lease, Millis maxHoldWhileWaited)
    : m_lease(lease), m_maxHoldWhileWaited(maxHoldWhileWaited) {
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

LockEvents LockArbiter::handleRequest(PeerId peer, Millis now) {
  LockEvents events;
  if (!m_holder) {
    grant(peer, now, events);
  } else if (m_holder->peer == peer) {
    // Idempotent: the holder asks again (e.g. it lost our Granted); repeat it to the holder only.
    m_holder->lastHeard = now;
    events.push_back(toPeer(peer, LockNotice{LockNoticeKind::Granted, peer, m_holder->epoch}));
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
  if (m_holder && m_holder->peer == peer && (epoch == kNoEpoch || epoch == m_holder->epoch)) {
    return endTenure(LockReleaseReason::Released, now);
  }
  if (epoch == kNoEpoch && removeFromQueue(peer)) {
    return {toPeer(peer, LockNotice{LockNoticeKind::Dequeued, peer})};
  }
  return ignore();  // release of a tenure the peer does not hold, or a cancel with nothing to cancel
}

LockEvents LockArbiter::handleRenew(PeerId peer, LockEpoch epoch, Millis now) {
  if (!m_holder || m_holder->peer != peer || m_holder->epoch != epoch) {
    return ignore();
  }
  m_holder->lastHeard = now;
  return {};
}

LockEvents LockArbiter::peerDisconnected(PeerId peer, Millis now) {
  if (m_holder && m_holder->peer == peer) {
    return endTenure(LockReleaseReason::Disconnected, now);
  }
  removeFromQueue(peer);  // nobody to notify: the peer is gone and positions are only told on request
  return {};
}

LockEvents LockArbiter::revokeByHost(Millis now) {
  if (!m_holder) return {};
  return endTenure(LockReleaseReason::RevokedByHost, now);
}

LockEvents LockArbiter::tick(Millis now) {
  if (m_holder && now - m_holder->lastHeard > m_lease) {
    return endTenure(LockReleaseReason::LeaseExpired, now);
  }
  if (m_holder && !m_queue.empty() && m_maxHoldWhileWaited.count() > 0 &&
      now - std::max(m_holder->grantedAt, m_waitingSince) > m_maxHoldWhileWaited) {
    ++m_revokedForWaiters;
    return endTenure(LockReleaseReason::LeaseExpired, now);
  }
  return {};
}

DragVerdict LockArbiter::acceptDrag(PeerId peer, LockEpoch epoch, Millis now) {
  if (!m_holder || m_holder->peer != peer) {
    return DragVerdict::NotHolder;
  }
  if (epoch != m_holder->epoch) {
    return DragVerdict::StaleEpoch;
  }
  m_holder->lastHeard = now;
  return DragVerdict::Accepted;
}

std::optional<Millis> LockArbiter::leaseDeadline() const {
  if (!m_holder) {
    return std::nullopt;
  }
  return m_holder->lastHeard + m_lease;
}

LockEvents LockArbiter::endTenure(LockReleaseReason reason, Millis now) {
  assert(m_holder && "endTenure needs a holder");
  LockEvents events{toAll(LockNotice{LockNoticeKind::Released, m_holder->peer, m_holder->epoch, 0, reason})};
  m_holder.reset();
  if (!m_queue.empty()) {
    const PeerId next = m_queue.front();
    m_queue.pop_front();
    grant(next, now, events);
  }
  return events;
}

void LockArbiter::grant(PeerId peer, Millis now, LockEvents& events) {
  assert(!m_holder && "never grant twice");
  m_holder = Holder{peer, ++m_lastEpoch, now, now};
  events.push_back(toAll(LockNotice{LockNoticeKind::Granted, peer, m_holder->epoch}));
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
