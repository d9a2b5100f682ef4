#include "session/engine/lock_client.h"

#include <algorithm>

#include <cassert>

namespace sc::session {

LockClient::LockClient(PeerId self, Millis renewEvery) : m_self(self), m_renewEvery(renewEvery) {
  assert(self != kNoPeer && "peer id 0 is reserved");
  assert(renewEvery.count() > 0 && "the renew period must be positive");
}

void LockClient::changeState(LockState next, Millis now, LockEpoch heldEpoch) {
  assert((next == LockState::Held) == (heldEpoch != kNoEpoch) && "exactly Held carries an epoch");
  m_state = next;
  m_heldEpoch = heldEpoch;
  if (next != LockState::Queued) {
    m_queuePosition = 0;
  }
  if (next == LockState::Held) {
    m_lastRenew = now;  // the grant itself refreshed the lease on the host
  }
}

std::optional<LockMessage> LockClient::request(Millis now) {
  if (m_state != LockState::Idle) {
    return std::nullopt;
  }
  m_lastLoss.reset();  // a new request: the last loss is history
  changeState(LockState::Requested, now);
  return LockMessage{LockRequestKind::Request, kNoEpoch};
}

std::optional<LockMessage> LockClient::release(Millis now) {
  switch (m_state) {
    case LockState::Held: {
      const LockEpoch epoch = m_heldEpoch;
      changeState(LockState::Releasing, now);
      return LockMessage{LockRequestKind::Release, epoch};
    }
    case LockState::Requested:
    case LockState::Queued:
      // Cancel: kNoEpoch also covers a grant already on its way to us.
      changeState(LockState::Releasing, now);
      return LockMessage{LockRequestKind::Release, kNoEpoch};
    case LockState::Idle:
    case LockState::Releasing:
      break;
  }
  return std::nullopt;
}

std::optional<LockMessage> LockClient::apply(const LockNotice& notice, Millis now) {
  switch (notice.kind) {
    case LockNoticeKind::Granted:
      return onGranted(notice, now);
    case LockNoticeKind::Queued:
      onQueued(notice, now);
      return std::nullopt;
    case LockNoticeKind::Released:
      onReleased(notice, now);
      return std::nullopt;
    case LockNoticeKind::Dequeued:
      onDequeued(now);
      return std::nullopt;
    case LockNoticeKind::Waiting:
      onWaiting(notice);
      return std::nullopt;
    case LockNoticeKind::Refused:
      onRefused(notice);
      return std::nullopt;
  }
  return ignore();
}

std::optional<LockMessage> LockClient::pollRenew(Millis now) {
  if (m_state != LockState::Held || now - m_lastRenew < m_renewEvery) {
    return std::nullopt;
  }
  m_lastRenew = now;
  return LockMessage{LockRequestKind::Renew, m_heldEpoch};
}

std::optional<Millis> LockClient::nextRenewDue() const {
  if (m_state != LockState::Held) {
    return std::nullopt;
  }
  return m_lastRenew + m_renewEvery;
}

std::optional<LockMessage> LockClient::onGranted(const LockNotice& notice, Millis now) {
  if (notice.epoch != kNoEpoch && notice.epoch < m_holderEpoch) {
    return ignore();  // older than what we already know
  }
  m_holderEpoch = notice.epoch;
  forgetHolder(notice.peer);
  m_holders.push_back({notice.peer, notice.epoch});
  if (notice.peer != m_self) {
    return std::nullopt;  // several may hold at once: another's grant says nothing about ours
  }
  switch (m_state) {
    case LockState::Requested:
    case LockState::Queued:
    case LockState::Held:  // a repeated grant (re-request) or a refresh of the epoch
      changeState(LockState::Held, now, notice.epoch);
      return std::nullopt;
    case LockState::Releasing:
      return std::nullopt;  // our cancel crossed the grant; the host will release on receiving it
    case LockState::Idle:
      break;
  }
  ++m_ignored;
  return LockMessage{LockRequestKind::Release, notice.epoch};  // a grant nobody here wants: hand it back
}

void LockClient::onQueued(const LockNotice& notice, Millis now) {
  if (notice.peer != m_self || (m_state != LockState::Requested && m_state != LockState::Queued)) {
    ignore();
    return;
  }
  changeState(LockState::Queued, now);
  m_queuePosition = notice.queuePosition;
}

void LockClient::onReleased(const LockNotice& notice, Millis now) {
  const auto it = std::find(m_holders.begin(), m_holders.end(), LockHolding{notice.peer, notice.epoch});
  if (it != m_holders.end()) m_holders.erase(it);  // that lease is free until the next Granted
  if (notice.peer != m_self) {
    return;
  }
  if ((m_state == LockState::Held && notice.epoch == m_heldEpoch) || m_state == LockState::Releasing) {
    m_lastLoss = notice.reason;
    changeState(LockState::Idle, now);
    return;
  }
  ignore();
}

void LockClient::onWaiting(const LockNotice& notice) {
  m_waiting = notice.waiting;
  if (m_state != LockState::Queued) return;
  const auto it = std::find(m_waiting.begin(), m_waiting.end(), m_self);
  if (it != m_waiting.end()) m_queuePosition = static_cast<std::uint32_t>(it - m_waiting.begin()) + 1;
}

void LockClient::onRefused(const LockNotice& notice) {
  if (notice.peer != m_self || m_state != LockState::Held || notice.epoch != m_heldEpoch) {
    ignore();
    return;
  }
  m_refusal = LockRefusal{++m_refusalCount, notice.waiting};
}

void LockClient::forgetHolder(PeerId peer) {
  const auto it =
      std::find_if(m_holders.begin(), m_holders.end(), [peer](const LockHolding& h) { return h.peer == peer; });
  if (it != m_holders.end()) m_holders.erase(it);
}

std::vector<PeerId> LockClient::holders() const {
  std::vector<PeerId> out;
  for (const LockHolding& h : m_holders) out.push_back(h.peer);
  return out;
}

void LockClient::onDequeued(Millis now) {
  if (m_state == LockState::Releasing || m_state == LockState::Queued || m_state == LockState::Requested) {
    changeState(LockState::Idle, now);
    return;
  }
  ignore();
}

std::optional<LockMessage> LockClient::ignore() {
  ++m_ignored;
  return std::nullopt;
}

}  // namespace sc::session
