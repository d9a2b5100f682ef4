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
  // a stroke and a constraint set end with their holder's lease (released, revoked, gone)
  for (const LockEvent& event : events) {
    if (event.notice.kind == LockNoticeKind::Released) endEditing(event.notice.peer, now, out);
  }
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

namespace {

spectral::ConstraintSet toConstraintSet(const Constraints& constraints) {
  spectral::ConstraintSet set;
  for (const std::vector<std::uint32_t>& group : constraints.groups) {
    set.handles.push_back({std::vector<int>(group.begin(), group.end())});
  }
  set.anchors.assign(constraints.anchors.begin(), constraints.anchors.end());
  return set;
}

}  // namespace

bool HostEngine::admitConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set, Micros now,
                                  HostActions& out) {
  std::vector<PeerId> overlapping = m_shared.conflicts(peer, set);
  const double m = static_cast<double>(m_model->rowCount());
  const bool tooLarge = static_cast<double>(m_shared.idsWith(peer, set)) * m * m > m_options.maxConstraintWork;
  if (overlapping.empty() && !tooLarge) return true;
  ++m_counters.constraintsRejected;
  ++m_counters.constraintsOverlapping;
  LockNotice refused{LockNoticeKind::Refused, peer, epoch, 0, LockReleaseReason::Released, std::move(overlapping)};
  dispatchLock({LockEvent{LockAudience::OnePeer, peer, std::move(refused)}}, now, out);
  return false;
}

void HostEngine::handleConstraints(PeerId peer, const Constraints& constraints, Micros now, HostActions& out) {
  if (!constraintsWithinBounds(constraints) ||
      m_arbiter.acceptDrag(peer, constraints.epoch, toMillis(now)) != DragVerdict::Accepted) {
    ++m_counters.constraintsRejected;
    return;
  }
  spectral::ConstraintSet set = toConstraintSet(constraints);
  if (!admitConstraints(peer, constraints.epoch, set, now, out)) return;
  commitStroke(now, out, peer);  // its previous constraints' stroke ends here; the new set starts from this shape
  ++m_counters.constraintsAccepted;
  m_shared.set(peer, std::move(set));
  if (const auto it = m_strokes.find(peer); it != m_strokes.end()) it->second.received.clear();
  prepareUnion(out);
}

void HostEngine::prepareUnion(HostActions& out) {
  auto set = std::make_shared<spectral::ConstraintSet>(m_shared.combined());
  m_constraintsInFlight = ConstraintsInFlight{++m_constraintsTicket, m_shared.version()};
  out.add(PrepareConstraints{m_constraintsInFlight->ticket, std::move(set)});
}

HostActions HostEngine::onConstraintsPrepared(std::uint64_t ticket,
                                              std::optional<spectral::PreparedConstraints> prepared, Micros now) {
  HostActions out;
  if (!m_constraintsInFlight || m_constraintsInFlight->ticket != ticket) return finish(std::move(out));  // stale
  const std::uint64_t version = m_constraintsInFlight->version;
  if (!prepared || m_shared.version() != version) {
    m_constraintsInFlight.reset();
    if (prepared) prepareUnion(out);  // the union changed meanwhile: factor the current one
    return finish(std::move(out));
  }
  foldStrokes(now, out);  // with the deformer still solving the previous union
  m_constraintsInFlight.reset();
  m_deformer->install(std::move(*prepared), *m_Z);  // from the shape as it is now, not from rest
  m_installed = m_shared;
  if (m_pendingArrival && !m_shutDown) produceFrame(now, false, out);  // the poses that waited
  std::vector<PeerId> ending;
  for (const auto& [peer, stroke] : m_strokes) {
    if (stroke.ending) ending.push_back(peer);
  }
  for (const PeerId peer : ending) commitStroke(now, out, peer);  // their StrokeEnd came while they waited
  return finish(std::move(out));
}

bool HostEngine::applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set, Micros now,
                                  HostActions& out) {
  if (m_arbiter.acceptDrag(peer, epoch, toMillis(now)) != DragVerdict::Accepted) {
    ++m_counters.constraintsRejected;
    return false;
  }
  if (!admitConstraints(peer, epoch, set, now, out)) return false;
  commitStroke(now, out, peer);       // its previous constraints' stroke ends here; the new set starts from this shape
  SharedConstraints next = m_shared;  // commitStroke() folded every stroke and moved the base to the current shape
  next.set(peer, set);
  if (!m_deformer->setConstraints(next.combined(), *m_Z)) {
    ++m_counters.constraintsRejected;
    return false;
  }
  ++m_counters.constraintsAccepted;
  m_shared = std::move(next);
  m_installed = m_shared;
  m_constraintsInFlight.reset();  // a member's set still being factored is in this union too
  if (const auto it = m_strokes.find(peer); it != m_strokes.end()) it->second.received.clear();
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
  Stroke& stroke = m_strokes[peer];
  stroke.received = std::move(poses);
  stroke.unsolved = true;
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
