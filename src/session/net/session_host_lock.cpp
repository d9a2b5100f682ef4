// SessionHost: the lock (arbiter events to peers and to the host's own LockClient), constraints and drags (from
// peers and from the host's own user), and the coalescing of accepted poses into frames.

#include "session/net/session_host.h"

#include "session/wire/handle_transforms.h"
#include "session/net/host_peer_connection.h"
#include "session/engine/session_clock.h"
#include "session/net/session_host_peer.h"

#include <QtCore/QTimer>

#include <algorithm>

namespace sc::session {

// --- lock, constraints, drags

void SessionHost::dispatchLock(const LockEvents& events) {
  for (const LockEvent& event : events) {
    const bool toHost = event.audience == LockAudience::AllPeers || event.recipient == kHostPeer;
    const QByteArray frame = encodeControlMessage(event.notice);
    for (const auto& [id, peer] : m_peers) {
      if (!peer->connection->isWelcomed()) continue;
      if (event.audience == LockAudience::AllPeers || event.recipient == id) peer->connection->sendEncoded(frame);
    }
    if (toHost) {
      if (const std::optional<LockMessage> reply = m_localLock.apply(event.notice, now())) {
        dispatchLock(m_arbiter.handleMessage(kHostPeer, *reply, now()));
      }
    }
  }
  if (!events.empty()) emit lockChanged();
}

bool SessionHost::requestLock() {
  const std::optional<LockMessage> message = m_localLock.request(now());
  if (message) dispatchLock(m_arbiter.handleMessage(kHostPeer, *message, now()));
  return message.has_value();
}

bool SessionHost::releaseLock() {
  const std::optional<LockMessage> message = m_localLock.release(now());
  if (message) dispatchLock(m_arbiter.handleMessage(kHostPeer, *message, now()));
  return message.has_value();
}

bool SessionHost::setConstraints(const spectral::ConstraintSet& constraints) {
  return applyConstraints(kHostPeer, m_localLock.heldEpoch(), constraints);
}

bool SessionHost::drag(std::span<const spectral::HandleTransform> poses) {
  return acceptPose(kHostPeer, m_localLock.heldEpoch(), {poses.begin(), poses.end()}, sessionNow());
}

void SessionHost::handleConstraints(PeerId peer, const Constraints& constraints) {
  const auto n = static_cast<std::uint32_t>(m_model->vertexCount());
  const auto valid = [n](std::uint32_t id) { return id < n; };
  spectral::ConstraintSet set;
  bool idsValid = std::all_of(constraints.anchors.begin(), constraints.anchors.end(), valid);
  for (const std::vector<std::uint32_t>& group : constraints.groups) {
    idsValid = idsValid && std::all_of(group.begin(), group.end(), valid);
    if (!idsValid) break;
    set.handles.push_back({std::vector<int>(group.begin(), group.end())});
  }
  if (!idsValid) {
    ++m_counters.constraintsRejected;
    return;
  }
  set.anchors.assign(constraints.anchors.begin(), constraints.anchors.end());
  applyConstraints(peer, constraints.epoch, set);
}

bool SessionHost::applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set) {
  if (m_arbiter.acceptDrag(peer, epoch, now()) != DragVerdict::Accepted || !m_deformer->setConstraints(set)) {
    ++m_counters.constraintsRejected;
    return false;
  }
  ++m_counters.constraintsAccepted;
  m_pendingArrival.reset();  // a pose for the previous groups means nothing now
  return true;
}

void SessionHost::handleDrag(PeerId peer, const Drag& drag, Micros arrivedAt) {
  acceptPose(peer, drag.epoch, fromWire(drag.handles, m_deformer->constraints().handles.size()), arrivedAt);
}

bool SessionHost::acceptPose(PeerId peer, LockEpoch epoch, std::vector<spectral::HandleTransform> poses,
                             Micros arrivedAt) {
  switch (m_arbiter.acceptDrag(peer, epoch, now())) {
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
  m_pendingArrival = arrivedAt;
  if (m_coalesce->isActive()) return true;  // the pending timer sends the latest pose
  const Micros since = sessionNow() - m_lastDragFrameAt;
  const Micros spacing = std::chrono::duration_cast<Micros>(m_options.coalesce);
  if (since >= spacing) {
    produceFrame();
  } else {
    const auto wait = std::chrono::ceil<Millis>(spacing - since);
    m_coalesce->start(std::max<int>(1, static_cast<int>(wait.count())));
  }
  return true;
}

}  // namespace sc::session
