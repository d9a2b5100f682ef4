// MainWindow: going from one session to another (issue 16). A join from inside a session connects beside it
// (pendingJoin()) and replaces it only once live, so that a failed join keeps the session; and what a session
// leaves on show once it ended (Left or Failed): its last shape, nothing else (title, host identity, docks).

#include "app/gui/main_window.h"

#include "app/gui/client_controller.h"
#include "app/gui/host_controller.h"
#include "app/gui/session_docks.h"
#include "app/gui/session_presence.h"
#include "app/gui/viewer_controller.h"

#include <QFileInfo>

namespace sc::app {

void MainWindow::joinSession(const JoinSettings& settings) {
  dropPendingJoin();
  const QString title = tr("%1:%2 — ShapeCast").arg(settings.host).arg(settings.port);
  auto* session = new ClientController(this);
  if (!sessionActive()) {
    adoptSession(session);
    setWindowTitle(title);
    session->join(settings);
    updateSessionActions();
    return;
  }
  // In a session: the new one connects beside it and replaces it once live; a failed join keeps it.
  m_pendingJoin = session;
  connect(session, &SessionController::progress, this, &MainWindow::onProgress);
  connect(session, &SessionController::stateChanged, this, [this, session, title] {
    if (session == m_pendingJoin && session->state() == SessionController::State::Live) adoptPendingJoin(title);
  });
  connect(session, &SessionController::failed, this, [this, session](const QString& message) {
    if (session != m_pendingJoin) return;
    dropPendingJoin();
    updateSessionActions();
    reportSessionFailure(session, message + QLatin1Char(' ') + tr("You are still in the session you were in."));
  });
  session->join(settings);
  updateSessionActions();
}

void MainWindow::watchSession(const WatchSettings& settings) {
  dropPendingJoin();
  auto* session = new ViewerController(this);
  adoptSession(session);  // a current session leaves: a viewer is never a member
  setWindowTitle(tr("%1 through NATS — ShapeCast").arg(settings.sessionId));
  session->watch(settings);
  updateSessionActions();
  updateLockControls();
}

void MainWindow::adoptPendingJoin(const QString& title) {
  SessionController* joined = m_pendingJoin;
  m_pendingJoin = nullptr;
  joined->disconnect(this);
  adoptSession(joined);  // the session we were in leaves now
  setWindowTitle(title);
  // What arrived while it connected beside the old session: its level and latest frame.
  onSessionLevel(joined->displayLevel());
  if (joined->displayFrame().Z.size() > 0) onSessionFrame(joined->displayFrame());
  onSessionMesh();
  updateSessionActions();
  updateLockControls();
}

void MainWindow::dropPendingJoin() {
  if (m_pendingJoin == nullptr) return;
  SessionController* pending = m_pendingJoin;
  m_pendingJoin = nullptr;
  pending->disconnect(this);
  pending->leave();
  pending->deleteLater();
}

void MainWindow::onSessionEnded() {
  // The last shape stays; nothing else of the session: title, host identity, peers, figures, others' pointers.
  const auto* host = qobject_cast<const HostController*>(m_session);
  setWindowTitle(host != nullptr ? QFileInfo(host->settings().meshPath).fileName() + tr(" — ShapeCast")
                                 : tr("ShapeCast"));
  m_docks->bind(nullptr);
  m_presence->bind(nullptr);
  updateTimingLabel();
  emit sessionEnded();
}

}  // namespace sc::app
