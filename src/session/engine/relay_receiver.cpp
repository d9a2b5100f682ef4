#include "session/engine/relay_receiver.h"

#include <algorithm>
#include <utility>

namespace sc::session {

RelayReceiver::RelayReceiver(QString sessionId, std::optional<QByteArray> pin)
    : m_sessionId(std::move(sessionId)), m_pin(std::move(pin)) {}

RelayFactsStatus RelayReceiver::onFacts(QByteArrayView message) {
  const std::optional<QByteArrayView> body = relayBody(message);
  std::optional<RelayFacts> facts = body ? decodeRelayFactsBody(*body) : std::nullopt;
  if (!facts) {
    ++m_counts.malformed;
    return RelayFactsStatus::Malformed;
  }
  const QByteArray fingerprint = relayCertificateFingerprint(facts->certificateDer);
  const bool pinned = m_pin ? fingerprint == *m_pin : (!m_verifier || facts->certificateDer == m_facts.certificateDer);
  if (!pinned) {
    ++m_counts.badSignature;
    return RelayFactsStatus::WrongFingerprint;
  }
  auto verifier = std::make_unique<RelayVerifier>(facts->certificateDer, m_sessionId);
  if (!verifier->verify(message)) {
    ++m_counts.badSignature;
    return RelayFactsStatus::BadSignature;
  }
  if (m_verifier && facts->rowCount != m_facts.rowCount) {  // the session cannot change its m
    ++m_counts.malformed;
    return RelayFactsStatus::Malformed;
  }
  m_facts = std::move(*facts);
  m_verifier = std::move(verifier);
  if (!m_pin) m_pin = fingerprint;  // trust on first use, then pinned
  return RelayFactsStatus::None;
}

std::optional<RelayFrame> RelayReceiver::authentic(QByteArrayView message) {
  RelayError error = RelayError::None;
  const bool shared = m_shared && m_pin && m_shared->appliesTo(m_sessionId, *m_pin);
  std::optional<QByteArrayView> body;
  if (shared && m_shared->contains(message)) {
    body = relayBody(message);  // the same bytes verified by a receiver pinning the same host
  } else {
    body = m_verifier->verify(message, &error);
    if (body && shared) m_shared->remember(message);
  }
  if (!body) {
    ++(error == RelayError::BadSignature ? m_counts.badSignature : m_counts.malformed);
    return std::nullopt;
  }
  std::optional<RelayFrame> frame = decodeRelayFrameBody(*body);
  if (!frame || frame->Z.rows() != m_facts.rowCount) {
    ++m_counts.malformed;
    return std::nullopt;
  }
  return frame;
}

bool RelayReceiver::onKeyframe(QByteArrayView message, Micros now) {
  if (!m_verifier) return false;
  std::optional<RelayFrame> keyframe = authentic(message);
  if (!keyframe) return false;
  apply(std::move(*keyframe), now, /*live=*/false);
  startWithoutKeyframe(now);
  return true;
}

std::optional<RelayFrame> RelayReceiver::onReference(QByteArrayView message) {
  if (!m_verifier) return std::nullopt;
  return authentic(message);
}

void RelayReceiver::startWithoutKeyframe(Micros now) {
  m_joined = true;
  std::deque<QByteArray> buffered;
  buffered.swap(m_buffer);
  for (const QByteArray& message : buffered) onFrame(message, now);
}

bool RelayReceiver::onFrame(QByteArrayView message, Micros now) {
  if (!m_joined || !m_verifier) {
    if (static_cast<int>(m_buffer.size()) == kRelayJoinBuffer) {
      m_buffer.pop_front();
      ++m_counts.overflowed;
    }
    m_buffer.emplace_back(message.toByteArray());
    return false;
  }
  std::optional<RelayFrame> frame = authentic(message);
  return frame && apply(std::move(*frame), now, /*live=*/true);
}

bool RelayReceiver::apply(RelayFrame frame, Micros now, bool live) {
  if (m_frame) {
    const auto ahead = static_cast<std::int32_t>(frame.frame - *m_frame);  // serial-number arithmetic
    if (ahead <= 0) {
      ++m_counts.stale;
      return false;
    }
    // Frames between the keyframe and the first frame this viewer saw live were published before it subscribed.
    if (m_liveSeen) m_counts.lost += ahead - 1;
  }
  m_frame = frame.frame;
  m_Z = std::move(frame.Z);
  ++m_counts.applied;
  if (!live) return true;  // a keyframe's stamp is as old as the keyframe: no latency sample
  m_liveSeen = true;
  const Micros age = now - Micros{static_cast<std::int64_t>(frame.stampMicros)};
  m_latency.add(now, std::max(age, Micros{0}));
  return true;
}

RelayViewerStats RelayReceiver::stats(Micros now) const {
  RelayViewerStats out = m_counts;
  out.latencyP50Ms = m_latency.percentileMs(now, 0.5);
  out.latencyP99Ms = m_latency.percentileMs(now, 0.99);
  return out;
}

}  // namespace sc::session
