// HostEngine: the limits against a hostile member or stranger (docs/security.md, "Hostile member"): the per-peer
// send budget and stall deadline, the per-peer message and request rates (the latest request over its rate is kept
// and served when the rate allows), the bounds of a Constraints message and
// the wait of an address after wrong passwords.

#include "session/engine/host_engine.h"

#include <algorithm>

namespace sc::session {
namespace {

/// Wrong passwords are forgotten this long after an address's last one.
constexpr Micros kWrongPasswordMemory{std::chrono::minutes(10)};

}  // namespace

HostActions HostEngine::onSendQueue(PeerId id, const SendQueueReport& report, Micros now) {
  HostActions out;
  m_counters.peakSendQueueBytes = std::max(m_counters.peakSendQueueBytes, report.peakBytes);
  const auto it = m_peers.find(id);
  if (it == m_peers.end() || it->second.closing) return finish(std::move(out));
  const bool overBudget = report.overBudget || report.queuedBytes > m_options.sendBudgetBytes;
  const bool stalled = report.queuedBytes > 0 &&
                       now - report.lastDrained > std::chrono::duration_cast<Micros>(m_options.sendStallTimeout);
  if (!overBudget && !stalled) return finish(std::move(out));
  ++m_counters.slowPeersDropped;
  out.add(LogLine{QStringLiteral("peer %1 does not read (%2 bytes queued%3): dropped")
                      .arg(id)
                      .arg(report.queuedBytes)
                      .arg(overBudget ? QStringLiteral(", over the send budget") : QString())});
  closePeer(it->second, ClosePeer::How::Abort, out);  // onClosed() frees its lock
  return finish(std::move(out));
}

bool HostEngine::withinRates(Peer& peer, const ControlMessage& message, Micros now, HostActions& out) {
  if (!peer.messages.take(now)) {
    ++m_counters.floodingPeersDropped;
    out.add(LogLine{QStringLiteral("peer %1 sends too many messages: dropped").arg(peer.id)});
    closePeer(peer, ClosePeer::How::Abort, out);
    return false;
  }
  TokenBucket* bucket = nullptr;
  switch (messageType(message)) {
    case MessageType::LockRequest:
      if (std::get<LockMessage>(message).kind == LockRequestKind::Request) bucket = &peer.lockRequests;
      break;
    case MessageType::ResolutionRequest:
      bucket = &peer.resolutionRequests;
      break;
    case MessageType::Constraints:
      bucket = &peer.constraints;
      break;
    case MessageType::EditRequest:
      bucket = &peer.editRequests;
      break;
    default:
      break;
  }
  if (bucket == nullptr || bucket->take(now)) return true;
  ++m_counters.requestsThrottled;
  if (const auto* resolution = std::get_if<ResolutionRequest>(&message)) peer.deferredResolution = *resolution;
  if (const auto* constraints = std::get_if<Constraints>(&message)) peer.deferredConstraints = *constraints;
  return false;
}

void HostEngine::serveDeferredRequests(Micros now, HostActions& out) {
  for (auto& [id, peer] : m_peers) {
    if (!peer.member()) continue;
    if (peer.deferredResolution && peer.resolutionRequests.take(now)) {
      const ResolutionRequest request = *peer.deferredResolution;
      peer.deferredResolution.reset();
      handleResolutionRequest(peer, request, out);
    }
    if (peer.deferredConstraints && peer.constraints.take(now)) {
      const Constraints constraints = std::move(*peer.deferredConstraints);
      peer.deferredConstraints.reset();
      handleConstraints(id, constraints, now, out);
    }
  }
}

bool HostEngine::constraintsWithinBounds(const Constraints& constraints) const {
  const auto n = static_cast<std::size_t>(m_model->vertexCount());
  std::vector<std::uint32_t> ids(constraints.anchors.begin(), constraints.anchors.end());
  for (const std::vector<std::uint32_t>& group : constraints.groups) {
    if (group.empty()) return false;
    ids.insert(ids.end(), group.begin(), group.end());
  }
  const double m = static_cast<double>(m_model->rowCount());
  if (static_cast<double>(ids.size()) * m * m > m_options.maxConstraintWork) return false;
  std::sort(ids.begin(), ids.end());
  return (ids.empty() || ids.back() < n) && std::adjacent_find(ids.begin(), ids.end()) == ids.end();
}

void HostEngine::wrongPassword(const Peer& peer, Micros now, HostActions& out) {
  ++m_counters.wrongPasswords;
  if (!m_wrongPasswords.contains(peer.address) && m_wrongPasswords.size() >= kMaxTrackedAddresses) {
    const auto oldest = std::min_element(m_wrongPasswords.begin(), m_wrongPasswords.end(),
                                         [](const auto& a, const auto& b) { return a.second.last < b.second.last; });
    m_wrongPasswords.erase(oldest);
  }
  WrongPasswords& record = m_wrongPasswords[peer.address];
  ++record.count;
  record.last = now;
  const int over = record.count - m_options.freeWrongPasswords;
  if (over > 0) {
    const Micros base = std::chrono::duration_cast<Micros>(m_options.wrongPasswordBackoff);
    const Micros cap = std::chrono::duration_cast<Micros>(m_options.maxWrongPasswordBackoff);
    const Micros wait = over > 20 ? cap : std::min(cap, base * (std::int64_t{1} << (over - 1)));
    record.notBefore = now + wait;
  }
  out.add(LogLine{QStringLiteral("wrong password from %1 (%2 in a row)")
                      .arg(QString::fromStdString(peer.address))
                      .arg(record.count)});
}

bool HostEngine::addressWaiting(const std::string& address, Micros now) const {
  const auto it = m_wrongPasswords.find(address);
  return it != m_wrongPasswords.end() && now < it->second.notBefore;
}

void HostEngine::forgetOldWrongPasswords(Micros now) {
  std::erase_if(m_wrongPasswords, [now](const auto& entry) { return now - entry.second.last > kWrongPasswordMemory; });
}

}  // namespace sc::session
