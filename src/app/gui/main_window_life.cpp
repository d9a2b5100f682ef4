// MainWindow: the life of a session seen from the window (issue 15). The questions before a session ends (quit,
// leave or open another mesh while hosting or joined), the host's moderation (Peers context menu and the lock
// toolbar: remove a member, take the lock back) and Session → Copy Invitation.

#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/gui/host_controller.h"
#include "app/gui/host_dialog.h"
#include "app/gui/invitation.h"
#include "app/gui/peers_dock.h"
#include "app/gui/session_docks.h"
#include "model/peer_table_model.h"

#include <QClipboard>
#include <QCloseEvent>
#include <QFileInfo>
#include <QGuiApplication>
#include <QMenu>
#include <QStatusBar>
#include <QTableView>
#include <QTimer>
#include <QToolBar>

#include <algorithm>
#include <optional>

namespace sc::app {

void MainWindow::setUpSessionLife() {
  // Session → Copy Invitation (after Session Info…), and the host's "Take back the lock" in the menu and toolbar.
  QAction* invitation = ui->menuSession->addAction(tr("&Copy Invitation"));
  invitation->setObjectName(QStringLiteral("actionCopyInvitation"));
  invitation->setStatusTip(tr("Copy this session's address, certificate fingerprint and join command"));
  connect(invitation, &QAction::triggered, this, [this] { copyInvitation(); });
  QAction* takeBack = ui->menuSession->addAction(tr("&Take Back the Lock"));
  takeBack->setObjectName(QStringLiteral("actionForceRelease"));
  takeBack->setStatusTip(tr("Release the locks their holders have (the next in the queue get them)"));
  ui->sessionToolBar->insertAction(ui->actionLock, takeBack);
  connect(takeBack, &QAction::triggered, this, [this] {
    if (m_session != nullptr) m_session->forceReleaseLock();
  });
  const auto updateActions = [this, invitation, takeBack] {
    const bool liveHost = m_session != nullptr && m_session->role() == SessionController::Role::Host &&
                          m_session->state() == SessionController::State::Live;
    invitation->setEnabled(liveHost);
    bool othersHold = false;
    for (const session::PeerId holder : liveHost ? m_session->lockHolders() : std::vector<session::PeerId>{}) {
      othersHold = othersHold || holder != m_session->selfId();
    }
    takeBack->setVisible(liveHost);
    takeBack->setEnabled(othersHold);
  };
  connect(this, &MainWindow::sessionStarted, this, [this, updateActions](SessionController* controller) {
    connect(controller, &SessionController::stateChanged, this, updateActions);
    connect(controller, &SessionController::lockChanged, this, updateActions);
    updateActions();
  });
  updateActions();
  // The Peers table's context menu (a host's moderation).
  QTableView* table = m_docks->peersDock()->view();
  table->setContextMenuPolicy(Qt::CustomContextMenu);
  connect(table, &QWidget::customContextMenuRequested, this, [this, table](const QPoint& at) {
    const QModelIndex index = table->indexAt(at);
    if (!index.isValid()) return;
    m_docks->peersDock()->selectPeer(index.data(model::PeerTableModel::PeerIdRole).toUInt());
    const std::optional<quint32> peer = m_docks->peersDock()->selectedPeerId();
    if (QMenu* menu = peer ? peerContextMenu(*peer) : nullptr) menu->popup(table->viewport()->mapToGlobal(at));
  });
}

QMenu* MainWindow::peerContextMenu(quint32 peerId) {
  delete m_peerMenu;
  m_peerMenu = nullptr;
  if (m_session == nullptr || m_session->role() != SessionController::Role::Host ||
      m_session->state() != SessionController::State::Live) {
    return nullptr;
  }
  const auto peer = static_cast<session::PeerId>(peerId);
  const bool self = peer == m_session->selfId();
  const bool holds = m_session->holdsLock(peer);
  if (self && !holds) return nullptr;
  m_peerMenu = new QMenu(this);
  m_peerMenu->setObjectName(QStringLiteral("peerContextMenu"));
  if (!self) {
    QAction* remove = m_peerMenu->addAction(tr("Remove from Session"));
    remove->setObjectName(QStringLiteral("actionKickPeer"));
    connect(remove, &QAction::triggered, this, [this, peer] {
      if (m_session != nullptr && m_session->kick(peer)) {
        statusBar()->showMessage(tr("Removed peer %1 from the session.").arg(peer), kStatusMessageMs);
      }
    });
  }
  if (holds) {
    QAction* release = m_peerMenu->addAction(self ? tr("Release the Lock") : tr("Take Back the Lock"));
    release->setObjectName(QStringLiteral("actionPeerForceRelease"));
    connect(release, &QAction::triggered, this, [this, peer] {
      if (m_session != nullptr) m_session->forceReleaseLock(peer);
    });
  }
  return m_peerMenu;
}

QString MainWindow::copyInvitation() {
  if (m_session == nullptr || m_session->role() != SessionController::Role::Host ||
      m_session->state() != SessionController::State::Live) {
    return {};
  }
  const QString text = invitationText(reachableAddress(), m_session->tcpPort(), m_session->hostFingerprint());
  if (text.isEmpty()) return {};
  QGuiApplication::clipboard()->setText(text);
  statusBar()->showMessage(tr("Copied the invitation (address, fingerprint, join command)."), kStatusMessageMs);
  return text;
}

// ---------------------------------------------------------------------------------------------------- questions

bool MainWindow::sessionActive() const {
  if (m_session == nullptr) return false;
  const SessionController::State state = m_session->state();
  return state == SessionController::State::Preparing || state == SessionController::State::Connecting ||
         state == SessionController::State::Live;
}

int MainWindow::othersInSession() const {
  if (m_session == nullptr || m_session->role() != SessionController::Role::Host ||
      m_session->state() != SessionController::State::Live) {
    return 0;
  }
  return std::max(0, static_cast<int>(m_session->peers().peers.size()) - 1);
}

SessionAnswer MainWindow::ask(const SessionQuestion& question) {
  if (m_sessionAsker) return m_sessionAsker(question);
  if (!m_errorDialogsEnabled) return SessionAnswer::End;
  return askInMessageBox(this, question);
}

bool MainWindow::leaveSessionAsking() {
  const int others = othersInSession();
  if (others > 0 && ask(endSessionQuestion(others)) == SessionAnswer::Cancel) return false;
  leaveSession();
  return true;
}

bool MainWindow::openMeshAsking(const QString& path, MeshLoad how) {
  const auto open = [this, &path, how] {
    if (how == MeshLoad::Now) return openMesh(path);
    loadMeshInBackground(path);  // the session ends once the mesh is read; a broken file keeps it
    return true;
  };
  if (!sessionActive()) return open();
  const QString opening = QFileInfo(path).fileName();
  const auto* host = qobject_cast<const HostController*>(m_session);
  const SessionAnswer answer =
      host != nullptr ? ask(openWhileHostingQuestion(QFileInfo(host->settings().meshPath).fileName(), opening))
                      : ask(openWhileJoinedQuestion(windowTitle().section(QStringLiteral(" — "), 0, 0), opening));
  switch (answer) {
    case SessionAnswer::Cancel:
      return false;
    case SessionAnswer::End:
      return open();  // ends the session first, once the mesh is read
    case SessionAnswer::Rehost:
      break;
  }
  // Host the new mesh instead: the Host dialog with it (port, password and name are the user's to choose again).
  HostDialog dialog(this);
  HostSettings settings = dialog.settings();
  settings.meshPath = path;
  dialog.setSettings(settings);
  if (dialog.exec() != QDialog::Accepted) return false;
  hostSession(dialog.settings());  // leaves the current session first
  return true;
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (m_closeConfirmed || !sessionActive()) {
    QMainWindow::closeEvent(event);
    return;
  }
  const int others = othersInSession();
  if (others > 0 && ask(endSessionQuestion(others)) == SessionAnswer::Cancel) {
    event->ignore();
    return;
  }
  // End the session (Leave{HostEnded} to every peer, or our Leave to the host), then close once the event loop has
  // written the Leaves: closing at once would end the process first and the peers would read "host lost".
  leaveSession();
  m_closeConfirmed = true;
  event->ignore();
  QTimer::singleShot(kLeaveFlushMs, this, &QWidget::close);
}

}  // namespace sc::app
