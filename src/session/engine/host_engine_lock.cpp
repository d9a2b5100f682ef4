// HostEngine: the lock (arbiter events to peers and to the host's own LockClient), constraints and poses (from
// peers and from the host's own user), and the coalescing of accepted poses into frames.

#include "session/engine/host_engine.h"

#include "session/wire/handle_transforms.h"

#include <algorithm>

namespace sc::session {

// --- lock

void HostEngine::dispatchLock(const LockEvents& events, Micros now, HostActions& out) {
  const Millis t = toMillis(now);
  for (const LockEvent& event : events) {
    if (event.audience == LockAudience::AllPeers) {
      out.add(SendToAll{event.notice});
    } else if (welcomed(event.recipient) != nullptr) {
      out.add(SendToPeer{event.recipient, event.notice});
    }
    const bool toHost = event.audience == LockAudience::AllPeers || event.recipient == kHostPeer;
    if (toHost) {
      if (const std::optional<LockMessage> reply = m_localLock.apply(event.notice, t)) {
        dispatchLock(m_arbiter.handleMessage(kHostPeer, *reply, t), now, out);
      }
    }
  }
  const bool queueChanged = announceLockQueue(now, out);
  // a stroke ends with its author's tenure (released, revoked, gone): what it did is a step of the history
  if (!events.empty() && m_strokeAuthor != kNoPeer && m_arbiter.holder() != m_strokeAuthor) commitStroke(now, out);
  if (!events.empty() || queueChanged) out.add(LockChanged{});
}

HostActions HostEngine::requestLock(Micros now, bool* sent) {
  return localLockMessage(m_localLock.request(toMillis(now)), now, sent);
}

HostActions HostEngine::releaseLock(Micros now, bool* sent) {
  return localLockMessage(m_localLock.release(toMillis(now)), now, sent);
}

HostActions HostEngine::localLockMessage(const std::optional<LockMessage>& message, Micros now, bool* sent) {
  HostActions out;
  if (message) dispatchLock(m_arbiter.handleMessage(kHostPeer, *message, toMillis(now)), now, out);
  if (sent) *sent = message.has_value();
  return finish(std::move(out));
}

// --- constraints and poses

HostActions HostEngine::setConstraints(const spectral::ConstraintSet& constraints, Micros now, bool* accepted) {
  HostActions out;
  const bool ok = applyConstraints(kHostPeer, m_localLock.heldEpoch(), constraints, now, out);
  if (accepted) *accepted = ok;
  return finish(std::move(out));
}

HostActions HostEngine::drag(std::span<const spectral::HandleTransform> poses, Micros now, bool* accepted) {
  HostActions out;
  const bool ok = acceptPose(kHostPeer, m_localLock.heldEpoch(), {poses.begin(), poses.end()}, now, now, out);
  if (accepted) *accepted = ok;
  return finish(std::move(out));
}

void HostEngine::handleConstraints(PeerId peer, const Constraints& constraints, Micros now, HostActions& out) {
  if (!constraintsWithinBounds(constraints) ||
      m_arbiter.acceptDrag(peer, constraints.epoch, toMillis(now)) != DragVerdict::Accepted) {
    ++m_counters.constraintsRejected;
    return;
  }
  auto set = std::make_shared<spectral::ConstraintSet>();
  for (const std::vector<std::uint32_t>& group : constraints.groups) {
    set->handles.push_back({std::vector<int>(group.begin(), group.end())});
  }
  set->anchors.assign(constraints.anchors.begin(), constraints.anchors.end());
  commitStroke(now, out);  // the previous constraints' stroke ends here; the new set starts from this shape
  ++m_counters.constraintsAccepted;
  m_pendingArrival.reset();  // a pose for the previous groups means nothing now
  m_coalesceDue.reset();
  m_constraintsInFlight = ConstraintsInFlight{++m_constraintsTicket, constraints.epoch, set->handles.size()};
  out.add(PrepareConstraints{m_constraintsInFlight->ticket, std::move(set)});
}

HostActions HostEngine::onConstraintsPrepared(std::uint64_t ticket,
                                              std::optional<spectral::PreparedConstraints> prepared, Micros now) {
  HostActions out;
  if (!m_constraintsInFlight || m_constraintsInFlight->ticket != ticket) return finish(std::move(out));  // stale
  const LockEpoch epoch = m_constraintsInFlight->epoch;
  m_constraintsInFlight.reset();
  if (!prepared || m_arbiter.epoch() != epoch) {
    m_pendingArrival.reset();  // its poses were for these constraints
    return finish(std::move(out));
  }
  m_deformer->install(std::move(*prepared), *m_Z);                     // from the shape as it is now, not from rest
  if (m_pendingArrival && !m_shutDown) produceFrame(now, false, out);  // the poses that waited
  return finish(std::move(out));
}

bool HostEngine::applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set, Micros now,
                                  HostActions& out) {
  if (m_arbiter.acceptDrag(peer, epoch, toMillis(now)) != DragVerdict::Accepted) {
    ++m_counters.constraintsRejected;
    return false;
  }
  commitStroke(now, out);  // the previous constraints' stroke ends here; the new set starts from this shape
  if (!m_deformer->setConstraints(set, *m_Z)) {
    ++m_counters.constraintsRejected;
    return false;
  }
  ++m_counters.constraintsAccepted;
  m_constraintsInFlight.reset();  // a member's set still being factored is superseded
  m_pendingArrival.reset();       // a pose for the previous groups means nothing now
  return true;
}

bool HostEngine::acceptPose(PeerId peer, LockEpoch epoch, std::vector<spectral::HandleTransform> poses,
                            Micros arrivedAt, Micros now, HostActions& out) {
  switch (m_arbiter.acceptDrag(peer, epoch, toMillis(now))) {
    case DragVerdict::NotHolder:
      ++m_counters.dragsNotHolder;
      return false;
    case DragVerdict::StaleEpoch:
      ++m_counters.dragsStale;
      return false;
    case DragVerdict::Accepted:
      break;
  }
  ++m_counters.dragsAccepted;
  m_pendingPoses = std::move(poses);
  m_pendingAuthor = peer;
  m_pendingArrival = arrivedAt;
  if (m_coalesceDue || m_constraintsInFlight) return true;  // the pending frame (or the install) sends it
  const Micros since = now - m_lastDragFrameAt;
  const Micros spacing = std::chrono::duration_cast<Micros>(m_options.coalesce);
  if (since >= spacing) {
    produceFrame(now, false, out);
  } else {
    m_coalesceDue = now + std::max<Micros>(Millis{1}, std::chrono::ceil<Millis>(spacing - since));
  }
  return true;
}

}  // namespace sc::session
