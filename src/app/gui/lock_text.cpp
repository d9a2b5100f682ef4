#include "app/gui/lock_text.h"

#include <QCoreApplication>
#include <QStringList>

#include <algorithm>

namespace sc::app {

namespace {

QString tr(const char* text) { return QCoreApplication::translate("SessionController", text); }

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

QString peerName(session::PeerId id, const session::PeerList& peers) {
  for (const session::PeerInfo& peer : peers.peers) {
    if (peer.peerId == id && !peer.name.isEmpty()) return peer.name;
  }
  return tr("peer %1").arg(id);
}

/// " — bob is waiting", " — bob and carol are waiting", " — bob, carol, dan and 2 others are waiting"; empty when
/// nobody else waits.
QString waitingText(const session::LockClient& lock, session::PeerId self, const session::PeerList& peers) {
  QStringList names;
  int others = 0;
  for (const session::PeerId id : lock.waiting()) {
    if (id == self) continue;
    if (names.size() < kMaxWaitingNames) {
      names.push_back(peerName(id, peers));
    } else {
      ++others;
    }
  }
  if (names.isEmpty()) return {};
  if (others > 0) return tr(" — %1 and %2 others are waiting").arg(names.join(QStringLiteral(", "))).arg(others);
  if (names.size() == 1) return tr(" — %1 is waiting").arg(names.front());
  const QString last = names.takeLast();
  return tr(" — %1 and %2 are waiting").arg(names.join(QStringLiteral(", ")), last);
}

/// "bob", "bob and carol", "bob, carol and dan" (every name: at most maxEditors ≤ kMaxPeers of them).
QString namesText(const std::vector<session::PeerId>& ids, const session::PeerList& peers) {
  QStringList names;
  for (const session::PeerId id : ids) names.push_back(peerName(id, peers));
  if (names.size() <= 1) return names.join(QString());
  const QString last = names.takeLast();
  return tr("%1 and %2").arg(names.join(QStringLiteral(", ")), last);
}

}  // namespace

QString lockText(const session::LockClient& lock, const std::vector<session::PeerId>& holders, session::PeerId self,
                 const session::PeerList& peers) {
  const bool selfHolds = lock.canDrag() && std::find(holders.begin(), holders.end(), self) != holders.end();
  std::vector<session::PeerId> others;
  for (const session::PeerId id : holders) {
    if (id != self || !selfHolds) others.push_back(id);
  }
  QString text;
  if (selfHolds) {
    text = tr("You hold the lock");
    if (others.size() == 1) text += tr(" — %1 drags too").arg(namesText(others, peers));
    if (others.size() > 1) text += tr(" — %1 drag too").arg(namesText(others, peers));
    text += waitingText(lock, self, peers);
  } else if (others.empty()) {
    text = tr("Lock free");
  } else if (others.size() == 1) {
    text = tr("Lock held by %1").arg(peerName(others.front(), peers));
  } else {
    text = tr("Locks held by %1").arg(namesText(others, peers));
  }
  switch (lock.state()) {
    case session::LockState::Requested:
      text += tr(" — requesting…");
      break;
    case session::LockState::Queued:
      text += tr(" — you are %1 in the queue").arg(ordinal(lock.queuePosition()));
      break;
    case session::LockState::Releasing:
      text += tr(" — releasing…");
      break;
    case session::LockState::Idle:
      if (lock.lastLoss() == session::LockReleaseReason::RevokedByHost) text += tr(" — the host released your lock");
      break;
    case session::LockState::Held:
      break;
  }
  return text;
}

QString refusalText(const session::LockRefusal& refusal, const session::PeerList& peers) {
  if (refusal.holders.empty()) {
    return tr("Too many handle and anchor vertices for everybody together: paint fewer");
  }
  return tr("Your handle or anchors overlap %1's: paint where nobody else holds")
      .arg(namesText(refusal.holders, peers));
}

QString lockActionText(const session::LockClient& lock) {
  switch (lock.state()) {
    case session::LockState::Requested:
    case session::LockState::Queued:
      return tr("Cancel request");
    case session::LockState::Held:
    case session::LockState::Releasing:
      return tr("Release lock");
    case session::LockState::Idle:
      break;
  }
  return tr("Request lock");
}

}  // namespace sc::app
