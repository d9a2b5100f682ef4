// HostEngine: construction, start/shutdown, queries and the cadences (housekeeping, heartbeat) that tick() runs.
// Membership and transfers are in host_engine_peers.cpp, the lock, constraints and poses in host_engine_lock.cpp,
// frame production in host_engine_frames.cpp.

#include "session/engine/host_engine.h"

#include <algorithm>

namespace sc::session {
namespace {

/// The next run of a periodic task that was due at `due` and ran at `now`: one period on, or one period after
/// `now` when that is already past (a late run is not repeated, like a periodic QTimer).
Micros nextPeriod(Micros due, Micros period, Micros now) { return due + period > now ? due + period : now + period; }

}  // namespace

HostEngine::HostEngine(std::shared_ptr<const HostModel> model, HostEngineOptions options,
                       const std::vector<std::uint32_t>& ladderTargets)
    : m_model(std::move(model)),
      m_options(std::move(options)),
      m_ladder(static_cast<std::uint32_t>(m_model->vertexCount()), ladderTargets),
      m_arbiter(kLockLease, m_options.maxLockHoldWhileWaited, std::clamp(m_options.maxEditors, 1, kMaxPeers)) {
  m_deformer =
      std::make_unique<spectral::SpectralDeformer>(m_model->basis, m_model->operators, m_model->V, m_options.deformer);
  m_Z = std::make_shared<const Eigen::MatrixXd>(Eigen::MatrixXd::Zero(m_model->rowCount(), 3));
}

HostEngine::~HostEngine() = default;

HostActions HostEngine::start(Micros now) {
  m_options.maxPeers = std::clamp(m_options.maxPeers, 1, kMaxPeers - 1);
  m_options.maxEditors = m_arbiter.maxHolders();
  m_options.maxPendingHandshakes = std::max(m_options.maxPendingHandshakes, 1);
  m_options.maxPendingPerAddress = std::max(m_options.maxPendingPerAddress, 1);
  m_options.handshakeTimeout = std::max(m_options.handshakeTimeout, Millis{1});
  m_options.sendBudgetBytes = std::max<std::int64_t>(m_options.sendBudgetBytes, 1);
  m_options.sendStallTimeout = std::max(m_options.sendStallTimeout, Millis{1});
  m_options.freeWrongPasswords = std::max(m_options.freeWrongPasswords, 0);
  m_started = true;
  m_lastFrameAt = now;
  m_nextHousekeeping = now + kHousekeepingPeriod;
  m_nextHeartbeat = now + kHeartbeatPeriod;
  return finish({});
}

HostActions HostEngine::shutdown(Micros /*now*/) {
  HostActions out;
  if (m_shutDown) return finish(std::move(out));
  m_shutDown = true;
  m_coalesceDue.reset();
  m_stillDue.reset();
  for (auto& [id, peer] : m_peers) {
    if (peer.closing) continue;
    if (peer.welcomed) {
      out.add(SendToPeer{id, Leave{LeaveReason::HostEnded, {}}});
    } else {
      out.add(
          SendToPeer{id, Refused{RefuseReason::ShuttingDown, kProtocolVersion, QStringLiteral("the host is closing")}});
    }
    closePeer(peer, ClosePeer::How::Graceful, out);
  }
  out.add(LogLine{QStringLiteral("session closed")});
  return finish(std::move(out));
}

HostActions HostEngine::tick(Micros now) {
  HostActions out;
  if (!m_started || m_shutDown) return finish(std::move(out));
  if (m_coalesceDue && now >= *m_coalesceDue) {
    m_coalesceDue.reset();
    produceFrame(now, false, out);
  }
  if (m_stillDue && now >= *m_stillDue) {
    m_stillDue.reset();
    produceStillFrame(now, out);
  }
  if (now >= m_nextHousekeeping) {
    m_nextHousekeeping = nextPeriod(m_nextHousekeeping, kHousekeepingPeriod, now);
    housekeeping(now, out);
  }
  if (now >= m_nextHeartbeat) {
    m_nextHeartbeat = nextPeriod(m_nextHeartbeat, kHeartbeatPeriod, now);
    heartbeat(now, out);
  }
  return finish(std::move(out));
}

HostActions HostEngine::finish(HostActions out) const {
  out.wakeAt = nextWakeUp();
  return out;
}

std::optional<Micros> HostEngine::nextWakeUp() const {
  if (!m_started || m_shutDown) return std::nullopt;
  Micros wake = std::min(m_nextHousekeeping, m_nextHeartbeat);
  if (m_coalesceDue) wake = std::min(wake, *m_coalesceDue);
  if (m_stillDue) wake = std::min(wake, *m_stillDue);
  return wake;
}

void HostEngine::housekeeping(Micros now, HostActions& out) {
  const Millis t = toMillis(now);
  for (const auto& [id, peer] : m_peers) {
    if (!peer.welcomed && !peer.closing && t - peer.acceptedAt > m_options.handshakeTimeout) {
      out.add(ExpireHandshake{id});
    }
  }
  forgetOldWrongPasswords(now);
  serveDeferredRequests(now, out);
  const LockEvents lockEvents = m_arbiter.tick(t);
  if (m_arbiter.revokedForWaiters() > m_counters.locksRevokedForWaiters) {
    m_counters.locksRevokedForWaiters = m_arbiter.revokedForWaiters();
    out.add(LogLine{QStringLiteral("lock revoked: held too long while others waited")});
  }
  dispatchLock(lockEvents, now, out);
  if (const std::optional<LockMessage> renew = m_localLock.pollRenew(t)) {
    dispatchLock(m_arbiter.handleMessage(kHostPeer, *renew, t), now, out);
  }
  const bool idle = now - m_lastFrameAt >= std::chrono::duration_cast<Micros>(m_options.idleRefresh);
  if (idle && !m_coalesceDue) produceFrame(now, false, out);
}

void HostEngine::heartbeat(Micros now, HostActions& out) {
  const Millis t = toMillis(now);
  const Heartbeat beat{m_heartbeatSequence++};
  for (auto& [id, peer] : m_peers) {
    if (!peer.member()) continue;
    if (t - peer.lastHeard > m_options.peerTimeout) {
      ++m_counters.silentPeersDropped;
      out.add(LogLine{QStringLiteral("peer %1 silent for too long: dropped").arg(id)});
      closePeer(peer, ClosePeer::How::Abort, out);
    } else {
      out.add(SendToPeer{id, beat});
    }
  }
}

void HostEngine::closePeer(Peer& peer, ClosePeer::How how, HostActions& out) {
  peer.closing = true;
  out.add(ClosePeer{peer.id, how});
}

HostEngine::Peer* HostEngine::welcomed(PeerId id) {
  const auto it = m_peers.find(id);
  return it == m_peers.end() || !it->second.welcomed ? nullptr : &it->second;
}

std::optional<StatsReport> HostEngine::stats(PeerId peer) const {
  const auto it = m_peers.find(peer);
  return it == m_peers.end() ? std::nullopt : it->second.stats;
}

PeerList HostEngine::peerList() const {
  PeerList list;
  list.peers.push_back({kHostPeer, static_cast<std::uint32_t>(m_model->vertexCount()), m_options.hostName});
  for (const auto& [id, peer] : m_peers) {
    if (peer.member()) list.peers.push_back({id, peer.loadedVertexCount, peer.name});
  }
  return list;
}

bool HostEngine::sessionFull() const {
  const auto members = std::count_if(m_peers.begin(), m_peers.end(), [](const auto& e) { return e.second.member(); });
  return members >= m_options.maxPeers;
}

bool HostEngine::nameTaken(const QString& name) const {
  if (name == m_options.hostName) return true;
  return std::any_of(m_peers.begin(), m_peers.end(),
                     [&name](const auto& entry) { return entry.second.welcomed && entry.second.name == name; });
}

}  // namespace sc::session
