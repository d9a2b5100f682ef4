// SessionController, editing: the edit lock, the constraint set (displayed ids mapped to full-resolution ids) and
// drags of the handle, the same for a host and a client.
#include "app/gui/session_controller.h"

#include "session/wire/handle_transforms.h"
#include "session/engine/host_model.h"
#include "session/net/session_client.h"
#include "session/net/session_host.h"
#include "spectral/resolution_level.h"
#include "spectral/spectral_deformer.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace sc::app {

namespace {

QString ordinal(std::uint32_t n) {
  if (n % 100 >= 11 && n % 100 <= 13) return QStringLiteral("%1th").arg(n);
  switch (n % 10) {
    case 1:
      return QStringLiteral("%1st").arg(n);
    case 2:
      return QStringLiteral("%1nd").arg(n);
    case 3:
      return QStringLiteral("%1rd").arg(n);
    default:
      return QStringLiteral("%1th").arg(n);
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------------- lock

bool SessionController::requestLock() {
  if (m_state != State::Live) return false;
  if (m_host != nullptr) return m_host->requestLock();
  return m_client != nullptr && m_client->requestLock();
}

bool SessionController::releaseLock() {
  if (m_state != State::Live) return false;
  m_dragging = false;
  if (m_host != nullptr) return m_host->releaseLock();
  return m_client != nullptr && m_client->releaseLock();
}

bool SessionController::canDrag() const {
  if (m_state != State::Live) return false;
  if (m_host != nullptr) return m_host->localLock().canDrag();
  return m_client != nullptr && m_client->lock() != nullptr && m_client->lock()->canDrag();
}

bool SessionController::lockWanted() const {
  if (m_state != State::Live) return false;
  const session::LockClient* lock = nullptr;
  if (m_host != nullptr) lock = &m_host->localLock();
  if (m_client != nullptr) lock = m_client->lock();
  return lock != nullptr && lock->state() != session::LockState::Idle;
}

session::PeerId SessionController::lockHolder() const {
  if (m_state != State::Live) return session::kNoPeer;
  if (m_host != nullptr) return m_host->lockHolder();
  if (m_client != nullptr && m_client->lock() != nullptr) return m_client->lock()->holder();
  return session::kNoPeer;
}

std::vector<session::PeerId> SessionController::lockQueue() const {
  if (m_state != State::Live || m_host == nullptr) return {};
  return {m_host->lockQueue().begin(), m_host->lockQueue().end()};
}

QString SessionController::lockText() const {
  if (m_state != State::Live) return {};
  const session::LockClient* lock = m_host != nullptr ? &m_host->localLock() : m_client->lock();
  if (lock == nullptr) return {};
  QString text;
  const session::PeerId holder = lockHolder();
  if (holder == selfId() && lock->canDrag()) {
    text = tr("You hold the lock");
  } else if (holder == session::kNoPeer) {
    text = tr("Lock free");
  } else {
    QString name = tr("peer %1").arg(holder);
    for (const session::PeerInfo& peer : peers().peers) {
      if (peer.peerId == holder && !peer.name.isEmpty()) name = peer.name;
    }
    text = tr("Lock held by %1").arg(name);
  }
  switch (lock->state()) {
    case session::LockState::Requested:
      text += tr(" — requesting…");
      break;
    case session::LockState::Queued:
      text += tr(" — you are %1 in the queue").arg(ordinal(lock->queuePosition()));
      break;
    case session::LockState::Releasing:
      text += tr(" — releasing…");
      break;
    case session::LockState::Idle:
    case session::LockState::Held:
      break;
  }
  return text;
}

void SessionController::onLockChanged() {
  const bool held = canDrag();
  if (held && !m_hadLock) {
    m_constraintsSent = false;
    sendConstraints();
  }
  if (!held) m_dragging = false;
  m_hadLock = held;
  emit lockChanged();
  emit peersChanged();  // the peers view shows the holder
}

// ---------------------------------------------------------------------------------------------------- constraints

std::vector<int> SessionController::toFullIds(const std::vector<int>& displayed) const {
  if (m_host == nullptr) {
    const spectral::ResolutionLevel* level = clientLevel();
    return level != nullptr ? spectral::dominantFullVertices(level->P, displayed) : std::vector<int>{};
  }
  // a host displays the full level: the displayed ids are the full ids
  const int n = m_model ? m_model->vertexCount() : 0;
  std::vector<int> ids;
  ids.reserve(displayed.size());
  std::copy_if(displayed.begin(), displayed.end(), std::back_inserter(ids), [n](int id) { return id >= 0 && id < n; });
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

bool SessionController::setHandle(std::vector<int> displayedIds) {
  m_handle = std::move(displayedIds);
  m_constraintsSent = false;
  return sendConstraints();
}

bool SessionController::setAnchors(std::vector<int> displayedIds) {
  m_anchors = std::move(displayedIds);
  m_constraintsSent = false;
  return sendConstraints();
}

bool SessionController::setSelection(std::vector<int> handle, std::vector<int> anchors) {
  m_handle = std::move(handle);
  m_anchors = std::move(anchors);
  m_constraintsSent = false;
  return sendConstraints();
}

bool SessionController::sendConstraints() {
  if (m_constraintsSent || !canDrag()) return false;
  const std::vector<int> handle = toFullIds(m_handle);
  if (handle.empty()) return false;
  std::vector<int> anchors = toFullIds(m_anchors);
  // a vertex cannot be both: the handle wins
  anchors.erase(std::remove_if(anchors.begin(), anchors.end(),
                               [&handle](int id) { return std::binary_search(handle.begin(), handle.end(), id); }),
                anchors.end());
  bool sent = false;
  if (m_host != nullptr) {
    spectral::ConstraintSet set;
    set.handles.push_back({handle});
    set.anchors = anchors;
    sent = m_host->setConstraints(set);
  } else if (m_client != nullptr) {
    sent = m_client->sendConstraints({std::vector<std::uint32_t>(handle.begin(), handle.end())},
                                     std::vector<std::uint32_t>(anchors.begin(), anchors.end()));
  }
  m_constraintsSent = sent;
  if (sent && m_host != nullptr) {
    m_sentHandle = handle;
    m_sentAnchors = anchors;
  }
  if (sent) {  // a new constraint set starts from rest
    m_baseRotation = m_lastRotation = Eigen::Matrix3d::Identity();
    m_baseTranslation = m_lastTranslation = Eigen::Vector3d::Zero();
  }
  return sent;
}

bool SessionController::beginDrag() {
  if (!canDrag() || m_handle.empty()) return false;
  if (!m_constraintsSent && !sendConstraints()) return false;
  m_baseRotation = m_lastRotation;
  m_baseTranslation = m_lastTranslation;
  m_dragging = true;
  return true;
}

bool SessionController::dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation) {
  if (!m_dragging || !canDrag()) return false;
  const spectral::HandleTransform pose =
      spectral::composeHandleTransforms({m_baseTranslation, m_baseRotation}, {translation, rotation});
  bool sent = false;
  if (m_host != nullptr) {
    sent = m_host->drag(std::span<const spectral::HandleTransform>(&pose, 1));
  } else if (m_client != nullptr) {
    sent = m_client->sendDrag({session::toWire(0, pose)});
  }
  if (sent) {
    m_lastRotation = pose.rotation;
    m_lastTranslation = pose.translation;
  }
  return sent;
}

void SessionController::endDrag() { m_dragging = false; }

std::optional<HostDeformation> SessionController::hostDeformation() const {
  if (m_host == nullptr || !m_constraintsSent) return std::nullopt;
  return HostDeformation{m_sentHandle, m_sentAnchors, m_lastTranslation, m_lastRotation};
}

bool SessionController::restoreHostDeformation(const HostDeformation& state) {
  if (m_host == nullptr || m_dragging || !canDrag() || state.handle.empty()) return false;
  spectral::ConstraintSet set;
  set.handles.push_back({state.handle});
  set.anchors = state.anchors;
  if (!m_host->setConstraints(set)) return false;
  const spectral::HandleTransform pose{state.translation, state.rotation};
  if (!m_host->drag(std::span<const spectral::HandleTransform>(&pose, 1))) return false;
  m_handle = m_sentHandle = state.handle;
  m_anchors = m_sentAnchors = state.anchors;
  m_constraintsSent = true;
  m_baseRotation = m_lastRotation = pose.rotation;
  m_baseTranslation = m_lastTranslation = pose.translation;
  return true;
}

}  // namespace sc::app
