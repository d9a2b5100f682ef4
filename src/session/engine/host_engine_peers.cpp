// HostEngine: membership (admission, welcome, incoming messages, closing) and the model transfers of the ladder's
// levels to peers.

#include "session/engine/host_engine.h"

#include "session/wire/handle_transforms.h"

#include <algorithm>

namespace sc::session {
namespace {

QString describe(MessageType type) {
  return QStringLiteral("0x%1").arg(static_cast<int>(type), 2, 16, QLatin1Char('0'));
}

}  // namespace

// --- connections

PeerId HostEngine::allocatePeerId() {
  for (int attempt = 0; attempt < 0xffff; ++attempt) {
    const PeerId id = m_nextPeerId;
    m_nextPeerId = id >= 0xffff ? kHostPeer + 1 : id + 1;
    if (!m_peers.contains(id)) return id;
  }
  return kNoPeer;
}

Admission HostEngine::onConnectionAttempt(const std::string& addressKey, Micros now) {
  Admission admission;
  if (m_shutDown) return admission;
  if (addressWaiting(addressKey, now)) {
    ++m_counters.connectionsThrottled;
    return admission;
  }
  int pending = 0;
  int fromAddress = 0;
  for (const auto& [id, peer] : m_peers) {
    if (peer.welcomed || peer.closing) continue;
    ++pending;
    if (peer.address == addressKey) ++fromAddress;
  }
  if (fromAddress >= m_options.maxPendingPerAddress) {
    ++m_counters.connectionsOverLimit;
    return admission;
  }
  if (pending >= m_options.maxPendingHandshakes) {
    admission.evict = evictionCandidate(fromAddress);
    if (admission.evict == kNoPeer) {
      ++m_counters.connectionsOverLimit;
      return admission;
    }
    ++m_counters.pendingEvicted;
    m_peers[admission.evict].closing = true;  // the adapter aborts it; onClosed() forgets it
  }
  admission.peer = allocatePeerId();
  if (admission.peer == kNoPeer) {
    ++m_counters.connectionsOverLimit;
    return admission;
  }
  Peer& peer = m_peers[admission.peer];
  peer.id = admission.peer;
  peer.address = addressKey;
  peer.acceptedAt = toMillis(now);
  peer.lastHeard = peer.acceptedAt;
  peer.messages = TokenBucket(m_options.messageRate);
  peer.lockRequests = TokenBucket(m_options.lockRequestRate);
  peer.resolutionRequests = TokenBucket(m_options.resolutionRequestRate);
  peer.editRequests = TokenBucket(m_options.editRequestRate);
  peer.constraints = TokenBucket(m_options.constraintsRate);
  peer.presence = TokenBucket(m_options.presenceRate);
  return admission;
}

PeerId HostEngine::evictionCandidate(int fromAddress) const {
  std::map<std::string, int> perAddress;
  for (const auto& [id, peer] : m_peers) {
    if (!peer.welcomed && !peer.closing) ++perAddress[peer.address];
  }
  const auto most = std::max_element(perAddress.begin(), perAddress.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  if (most == perAddress.end() || most->second <= fromAddress + 1) return kNoPeer;
  PeerId oldest = kNoPeer;
  Millis oldestAt{0};
  for (const auto& [id, peer] : m_peers) {
    if (peer.welcomed || peer.closing || peer.address != most->first) continue;
    if (oldest == kNoPeer || peer.acceptedAt < oldestAt) {
      oldest = id;
      oldestAt = peer.acceptedAt;
    }
  }
  return oldest;
}

HostActions HostEngine::onWelcomed(PeerId id, const QString& name, Micros /*now*/) {
  HostActions out;
  const auto it = m_peers.find(id);
  if (it == m_peers.end()) return finish(std::move(out));
  Peer& peer = it->second;
  peer.welcomed = true;
  peer.name = name;
  out.add(SendToAll{peerList()});
  // The exact level figures built so far; the rest of the ladder is built in the background and each new level
  // re-sends the list to everybody (onLevelReady).
  out.add(SendToPeer{id, m_ladder.levelList()});
  out.add(PrefetchLevels{});
  for (const LockHolding& lease : m_arbiter.holders()) {
    out.add(SendToPeer{id, LockNotice{LockNoticeKind::Granted, lease.peer, lease.epoch, 0, {}}});
  }
  if (!m_history.steps().empty()) out.add(SendToPeer{id, m_history.log()});
  if (!m_arbiter.queue().empty()) out.add(SendToPeer{id, waitingNotice()});
  out.add(LogLine{
      QStringLiteral("%1 joined as peer %2 from %3").arg(name).arg(id).arg(QString::fromStdString(peer.address))});
  out.add(PeersChanged{});
  return finish(std::move(out));
}

HostActions HostEngine::onRefused(PeerId id, RefuseReason reason, Micros now) {
  HostActions out;
  const auto index = static_cast<std::size_t>(reason);
  if (index < m_counters.refusals.size()) ++m_counters.refusals[index];
  const auto it = m_peers.find(id);
  if (it == m_peers.end()) return finish(std::move(out));
  it->second.closing = true;
  if (reason == RefuseReason::WrongPassword) wrongPassword(it->second, now, out);
  return finish(std::move(out));
}

HostActions HostEngine::onTlsFailed(PeerId id, const QString& why) {
  ++m_counters.tlsFailures;
  HostActions out;
  const auto it = m_peers.find(id);
  if (it == m_peers.end()) return finish(std::move(out));
  it->second.closing = true;
  const QString address = QString::fromStdString(it->second.address);
  out.add(LogLine{QStringLiteral("TLS handshake with %1 failed: %2").arg(address, why)});
  return finish(std::move(out));
}

void HostEngine::onHeard(PeerId id, Micros at) {
  if (const auto it = m_peers.find(id); it != m_peers.end()) it->second.lastHeard = toMillis(at);
}

HostActions HostEngine::onClosed(PeerId id, Micros now) {
  HostActions out;
  const auto it = m_peers.find(id);
  if (it == m_peers.end()) return finish(std::move(out));
  const bool wasMember = it->second.welcomed;
  if (m_strokes.contains(id)) commitStroke(now, out, id);  // its last stroke is a step, named while still listed
  m_peers.erase(m_peers.find(id));
  if (!wasMember) return finish(std::move(out));
  dispatchLock(m_arbiter.peerDisconnected(id, toMillis(now)), now, out);
  out.add(SendToAll{peerList()});
  out.add(LogLine{QStringLiteral("peer %1 left").arg(id)});
  out.add(PeersChanged{});
  return finish(std::move(out));
}

void HostEngine::protocolFailure(Peer& peer, const QString& why, HostActions& out) {
  ++m_counters.protocolErrors;
  out.add(LogLine{QStringLiteral("protocol error from peer %1 (%2): connection closed").arg(peer.id).arg(why)});
  closePeer(peer, ClosePeer::How::Graceful, out);
}

HostActions HostEngine::onDecodeError(PeerId id, const QString& why, Micros /*now*/) {
  HostActions out;
  if (Peer* peer = welcomed(id)) protocolFailure(*peer, why, out);
  return finish(std::move(out));
}

HostActions HostEngine::onMessage(PeerId id, const ControlMessage& message, Micros now) {
  HostActions out;
  Peer* peer = welcomed(id);
  if (peer == nullptr || peer->closing) return finish(std::move(out));
  if (!withinRates(*peer, message, now, out)) return finish(std::move(out));
  switch (messageType(message)) {
    case MessageType::ResolutionRequest:
      handleResolutionRequest(*peer, std::get<ResolutionRequest>(message), out);
      break;
    case MessageType::LockRequest:
      dispatchLock(m_arbiter.handleMessage(id, std::get<LockMessage>(message), toMillis(now)), now, out);
      break;
    case MessageType::Constraints:
      handleConstraints(id, std::get<Constraints>(message), now, out);
      break;
    case MessageType::Drag: {
      const Drag& drag = std::get<Drag>(message);
      const std::optional<GroupRange> range = m_shared.groups(id);  // its latest set, installed or on its way
      const std::size_t groups = range ? range->count : 0;
      acceptPose(id, drag.epoch, fromWire(drag.handles, groups), now, now, out);
      break;
    }
    case MessageType::StrokeEnd:
      if (m_arbiter.acceptDrag(id, std::get<StrokeEnd>(message).epoch, toMillis(now)) == DragVerdict::Accepted) {
        endStrokeOf(id, now, out);
      }
      break;
    case MessageType::EditRequest:
      applyEdit(id, std::get<EditRequest>(message).action, now, out);
      break;
    case MessageType::StatsReport:
      peer->stats = std::get<StatsReport>(message);
      out.add(StatsReported{id, *peer->stats});
      break;
    case MessageType::Presence:
      relayPresence(*peer, std::get<Presence>(message), now, out);
      break;
    case MessageType::Heartbeat:
      break;  // onHeard() already noted the bytes
    case MessageType::Leave:
      closePeer(*peer, ClosePeer::How::Abort, out);  // onClosed() cleans up
      break;
    default:
      protocolFailure(*peer, QStringLiteral("unexpected message %1").arg(describe(messageType(message))), out);
      break;
  }
  return finish(std::move(out));
}

// --- model transfer

void HostEngine::handleResolutionRequest(Peer& peer, const ResolutionRequest& request, HostActions& out) {
  const std::uint32_t target = m_ladder.pick(request.vertexCount);
  if (peer.transferring && peer.transferTarget == target) return;  // already on its way
  if (m_ladder.find(target)) {
    startTransfer(peer, target, out);
    return;
  }
  peer.waitingFor = target;
  out.add(RequestLevel{target});
}

void HostEngine::startTransfer(Peer& peer, std::uint32_t target, HostActions& out) {
  const LevelFigures* level = m_ladder.find(target);
  if (!level) return;
  peer.waitingFor.reset();
  if (++m_transferId == 0) m_transferId = 1;
  peer.transferTarget = target;
  peer.transferVertexCount = level->vertexCount;
  if (peer.closing) return;  // a closing connection starts nothing
  peer.transferring = true;
  out.add(StartTransfer{peer.id, m_transferId, target});
}

HostActions HostEngine::onLevelReady(std::uint32_t target, const LevelFigures& figures, Micros /*now*/) {
  HostActions out;
  m_ladder.setBuilt(target, figures);
  levelReady(target, out);
  return finish(std::move(out));
}

void HostEngine::levelReady(std::uint32_t target, HostActions& out) {
  out.add(SendToAll{m_ladder.levelList()});
  for (auto& [id, peer] : m_peers) {
    if (peer.waitingFor == target) startTransfer(peer, target, out);
  }
}

HostActions HostEngine::onLevelFailed(std::uint32_t target, const QString& reason, Micros /*now*/) {
  HostActions out;
  m_ladder.setFailed(target);
  out.add(LogLine{QStringLiteral("level %1 unavailable: %2").arg(target).arg(reason)});
  const std::uint32_t full = m_ladder.fullTarget();
  for (auto& [id, peer] : m_peers) {
    if (peer.waitingFor != target) continue;
    if (target == full) {
      peer.waitingFor.reset();  // nothing left to send
    } else {
      peer.waitingFor = full;  // fall back to the full model
    }
  }
  if (target != full) {
    if (m_ladder.find(full)) {
      levelReady(full, out);
    } else {
      out.add(RequestLevel{full});
    }
  }
  return finish(std::move(out));
}

HostActions HostEngine::onTransferFinished(PeerId id, Micros /*now*/) {
  HostActions out;
  const auto it = m_peers.find(id);
  if (it == m_peers.end()) return finish(std::move(out));
  Peer& peer = it->second;
  peer.transferring = false;
  peer.loadedVertexCount = peer.transferVertexCount;
  ++m_counters.transfersCompleted;
  sendKeyframe(id, out);
  out.add(SendToAll{peerList()});
  out.add(PeersChanged{});
  return finish(std::move(out));
}

}  // namespace sc::session
