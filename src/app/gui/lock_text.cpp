#include "app/gui/lock_text.h"

#include <QCoreApplication>

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

}  // namespace

QString lockText(const session::LockClient& lock, session::PeerId holder, session::PeerId self,
                 const session::PeerList& peers) {
  QString text;
  if (holder == self && lock.canDrag()) {
    text = tr("You hold the lock");
  } else if (holder == session::kNoPeer) {
    text = tr("Lock free");
  } else {
    QString name = tr("peer %1").arg(holder);
    for (const session::PeerInfo& peer : peers.peers) {
      if (peer.peerId == holder && !peer.name.isEmpty()) name = peer.name;
    }
    text = tr("Lock held by %1").arg(name);
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
    case session::LockState::Held:
      break;
  }
  return text;
}

}  // namespace sc::app
