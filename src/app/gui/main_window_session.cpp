// MainWindow: the session's life in the window: hosting, joining and leaving, the controller's signals back to the
// window (the frame path: its level and frames straight to the viewport), the lock, level and timing controls kept
// up to date, failures and progress. The controls are set up in main_window_session_setup.cpp.

#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/common/password_memory.h"
#include "app/gui/host_controller.h"
#include "app/gui/host_dialog.h"
#include "app/gui/interactive_proxy.h"
#include "app/gui/join_dialog.h"
#include "app/gui/mesh_summary.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/session_identity_view.h"
#include "app/gui/vertex_id_lists.h"

#include <QComboBox>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QLabel>
#include <QMessageBox>
#include <QProgressBar>
#include <QStatusBar>
#include <QToolButton>

#include <cstdio>
#include <optional>
#include <utility>

namespace sc::app {

// ---------------------------------------------------------------------------------------------------- sessions

void MainWindow::showHostDialog() {
  HostDialog dialog(this);
  if (dialog.exec() == QDialog::Accepted) hostSession(dialog.settings());
}

void MainWindow::showJoinDialog() {
  JoinDialog dialog(this);
  if (dialog.exec() == QDialog::Accepted) joinSession(dialog.settings());
}

void MainWindow::askPasswordAndJoin(const JoinSettings& retry, const QString& message) {
  JoinDialog dialog(this);
  dialog.setObjectName(QStringLiteral("passwordRetryDialog"));
  dialog.setSettings(retry);
  dialog.askForPassword(message);
  const std::optional<double> shownFraction = dialog.settings().levelFraction;
  if (dialog.exec() != QDialog::Accepted) return;
  JoinSettings again = dialog.settings();
  // What the form has no field for stays as it was: the emulated link, the known-hosts store, and the resolution
  // asked for (a vertex count or a percentage the form's choices lack) unless the user picked another.
  again.impairment = retry.impairment;
  again.knownHostsFile = retry.knownHostsFile;
  if (again.levelFraction == shownFraction) {
    again.level = retry.level;
    again.levelFraction = retry.levelFraction;
  }
  joinSession(again);
  forgetPassword(again.password);  // the session holds its own copy until its proof
}

void MainWindow::adoptSession(SessionController* controller) {
  if (m_session != nullptr) {
    m_session->disconnect(this);
    m_session->leave();
    m_session->deleteLater();
  }
  m_session = controller;
  // the frame path, one way: the controller's level and frames go to the viewport as they are
  connect(m_session, &SessionController::displayLevelChanged, this, &MainWindow::onSessionLevel);
  connect(m_session, &SessionController::frameChanged, this, &MainWindow::onSessionFrame);
  connect(m_session, &SessionController::meshChanged, this, &MainWindow::onSessionMesh);
  connect(m_session, &SessionController::lockChanged, this, &MainWindow::updateLockControls);
  connect(m_session, &SessionController::constraintsRefused, this,
          [this](const QString& message) { statusBar()->showMessage(message, kStatusMessageMs); });
  connect(m_session, &SessionController::peersChanged, this, &MainWindow::updateLockControls);
  connect(m_session, &SessionController::levelsChanged, this, &MainWindow::updateLevelCombo);
  connect(m_session, &SessionController::statsChanged, this, &MainWindow::updateTimingLabel);
  connect(m_session, &SessionController::stateChanged, this, [this] {
    updateSessionActions();
    updateLockControls();
    const SessionController::State state = m_session->state();
    if (state == SessionController::State::Left || state == SessionController::State::Failed) {
      m_levelDownloading = false;
      onSessionEnded();
    }
  });
  connect(m_session, &SessionController::failed, this, &MainWindow::onSessionFailed);
  connect(m_session, &SessionController::progress, this, &MainWindow::onProgress);
  connect(m_session, &SessionController::levelDownload, this, &MainWindow::onLevelDownload);
  connect(m_session, &SessionController::hostingStarted, this, [this](quint16 port) {
    statusBar()->showMessage(
        tr("Hosting on port %1. Others join with Session → Join and this computer's address.").arg(port),
        kStatusMessageMs);
  });
  emit sessionStarted(m_session);
}

bool MainWindow::hostSession(const HostSettings& settings, PortReservation port) {
  dropPendingJoin();
  // The port first, while the current session goes on: a busy port ends nothing. A current host on that very port
  // frees it when it leaves (adoptSession()); the new controller takes it then.
  const auto* current = qobject_cast<const HostController*>(m_session);
  const bool portOfCurrentHost = current != nullptr && sessionActive() && settings.port != 0 &&
                                 (current->settings().port == settings.port || current->tcpPort() == settings.port);
  if (!port.holds() && !portOfCurrentHost) {
    QString error;
    std::optional<PortReservation> taken = PortReservation::take(settings.port, &error);
    if (!taken) {
      reportSessionFailure(nullptr, error);
      return false;
    }
    port = std::move(*taken);
  }
  auto* session = new HostController(this);
  adoptSession(session);
  setWindowTitle(QFileInfo(settings.meshPath).fileName() + tr(" (hosting) — ShapeCast"));
  const bool started = session->host(settings, std::move(port));
  updateSessionActions();
  return started;
}

void MainWindow::leaveSession() {
  dropPendingJoin();
  if (m_session == nullptr) return;
  m_session->leave();
  statusBar()->showMessage(tr("Left the session."), kStatusMessageMs);
  updateSessionActions();
  updateLockControls();
}

double MainWindow::reconstructionMs() const { return m_viewReconstructMs; }

void MainWindow::onSessionLevel(const spectral::SharedDisplayLevel& level) {
  // The viewport holds the shared level and reconstructs rest + K·Z itself: in the vertex shader on the GPU path;
  // on the CPU path only the vertices its frame needs (the interactive proxy's while the shape moves).
  QElapsedTimer timer;
  timer.start();
  ui->viewport->setDisplayLevel(level);
  m_proxyBuilder->build(level);  // reads the shared level in place, on its worker thread
  if (m_reportLevelInstalls && level) {
    std::fprintf(stderr, "shapecast: level of %u vertices installed in %.1f ms on the GUI thread\n",
                 level->vertexCount(), static_cast<double>(timer.nsecsElapsed()) / 1e6);
    m_installPaintPending = true;
  }
}

void MainWindow::onSessionFrame(const spectral::DisplayFrame& frame) {
  // A still frame (the shape unchanged) draws nothing: no redraw to time. frameSwapped also follows every
  // composition of the window (a dock's repaint), which must not take the last frame's times as a new one.
  if (ui->viewport->showFrame(frame)) m_redrawPending = true;
}

void MainWindow::onSessionMesh() {
  const auto vertices = static_cast<int>(m_session->displayRestPositions().rows());
  m_meshSizeLabel->setText(meshSizeText(vertices, static_cast<int>(m_session->displayFaces().rows())));
  statusBar()->showMessage(tr("Showing %1 vertices").arg(vertices), kStatusMessageMs);
  updateLevelCombo();
  updateLockControls();
  showSessionSelection();  // the handle and anchors survive a resolution switch (the new level shows them)
}

void MainWindow::showSessionSelection() {
  if (m_session == nullptr) return;
  ui->viewport->setSelection(intIds<spectral::DisplayVertexTag>(m_session->handle()),
                             intIds<spectral::DisplayVertexTag>(m_session->anchors()));
}

void MainWindow::updateLockControls() {
  const bool live = m_session != nullptr && m_session->state() == SessionController::State::Live;
  if (const std::optional<QString> readOnly = m_session ? m_session->readOnlyText() : std::nullopt) {
    ui->actionLock->setEnabled(false);  // a viewer through NATS: nothing to lock, nothing to edit
    m_lockLabel->setText(*readOnly);
    ui->viewport->setDragAllowed(false, *readOnly);
    return;
  }
  ui->actionLock->setEnabled(live);
  ui->actionLock->setText(live ? m_session->lockActionText() : tr("Request lock"));
  m_lockLabel->setText(live ? m_session->lockText() : tr("Not in a session"));
  const bool canDrag = live && m_session->canDrag();
  QString hint;
  if (!live) {
    hint = tr("Host or join a session (Session menu) to deform the mesh");
  } else if (!canDrag) {
    hint = tr("Request the lock to drag (%1)").arg(m_session->lockText());
  }
  ui->viewport->setDragAllowed(canDrag, hint);
}

void MainWindow::updateLevelCombo() {
  m_levelCombo->clear();
  if (m_session == nullptr) {
    m_levelCombo->setEnabled(false);
    return;
  }
  const std::vector<LevelChoice> levels = m_session->levels();
  for (const LevelChoice& level : levels) {
    m_levelCombo->addItem(level.label, QVariant::fromValue<uint>(level.target));
    if (level.current) m_levelCombo->setCurrentIndex(m_levelCombo->count() - 1);
  }
  m_levelCombo->setEnabled(levels.size() > 1);  // a host has only its full level
}

void MainWindow::updateSessionActions() {
  const SessionController::State state = m_session != nullptr ? m_session->state() : SessionController::State::Idle;
  const bool active = state == SessionController::State::Preparing || state == SessionController::State::Connecting ||
                      state == SessionController::State::Live;
  ui->actionLeaveSession->setEnabled(active);
  const bool busy = meshLoadRunning() || m_pendingJoin != nullptr || state == SessionController::State::Preparing ||
                    state == SessionController::State::Connecting;
  m_progressBar->setVisible(busy || (m_levelDownloading && state == SessionController::State::Live));
  m_cancelButton->setVisible(busy);
  if (!active) m_levelCombo->setEnabled(false);
}

void MainWindow::updateTimingLabel() {
  if (m_session == nullptr || m_session->state() != SessionController::State::Live) {
    m_timingLabel->clear();
    m_timingLabel->setToolTip(QString());
    return;
  }
  // Plain words in the status bar, the precise figures in the tooltip (issue 16).
  const double reconstruction = reconstructionMs();
  QString text = tr("Frame: %1 ms").arg(reconstruction + m_redrawMs, 0, 'f', 1);
  QString detail = tr("reconstruction + redraw: %1 ms (%2 + %3)")
                       .arg(reconstruction + m_redrawMs, 0, 'f', 1)
                       .arg(reconstruction, 0, 'f', 2)
                       .arg(m_redrawMs, 0, 'f', 1);
  // How the frame was lightened while the shape moves (MeshViewport's adaptive resolution and proxy).
  m_labelFrame = ui->viewport->frameTimes();
  const bool proxy = m_labelFrame.triangles > 0 && m_labelFrame.triangles < ui->viewport->triangleCount();
  const int percent = qRound(100.0 * m_labelFrame.renderScale);
  if (proxy) {
    detail += tr("\nwhile moving: %L1 of %L2 triangles").arg(m_labelFrame.triangles).arg(ui->viewport->triangleCount());
  }
  if (percent < 100) detail += proxy ? tr(" at %1% scale").arg(percent) : tr("\nwhile moving: %1% scale").arg(percent);
  if (proxy || percent < 100) text += tr(" (lighter while moving)");
  if (text == m_timingLabel->text() && detail == m_timingLabel->toolTip()) return;  // no repaint for nothing new
  m_timingLabel->setText(text);
  m_timingLabel->setToolTip(detail);
}

void MainWindow::onSessionFailed(const QString& message) {
  updateSessionActions();
  updateLockControls();
  reportSessionFailure(m_session, message);
}

void MainWindow::reportSessionFailure(const SessionController* controller, const QString& message) {
  statusBar()->showMessage(message, kStatusMessageMs);
  emit sessionFailed(message);
  // The user's own Cancel is no error: the status bar says "Cancelled.", no dialog.
  if (!m_errorDialogsEnabled || (controller != nullptr && controller->cancelledByUser())) return;
  if (controller != nullptr && controller->fingerprintRefused()) {
    QMessageBox box(QMessageBox::Critical, tr("Host fingerprint does not match"), message, QMessageBox::Ok, this);
    box.setTextFormat(Qt::PlainText);  // the reason may quote the host: never rich text
    box.setObjectName(QStringLiteral("fingerprintRefusedBox"));
    box.setInformativeText(fingerprintRefusedAdvice());
    box.exec();
    return;
  }
  if (controller != nullptr) {
    if (const std::optional<JoinSettings> retry = controller->passwordRetry()) {
      // After the failing client has finished reporting (this runs inside its signal): the form is modal.
      QMetaObject::invokeMethod(
          this, [this, settings = *retry, message] { askPasswordAndJoin(settings, message); }, Qt::QueuedConnection);
      return;
    }
  }
  // The reason is often the host's own Refused text: shown as plain text, never rich text (no links or images a
  // hostile host could plant; docs/security.md, "Hostile host").
  QMessageBox box(QMessageBox::Warning, tr("Session"), message, QMessageBox::Ok, this);
  box.setTextFormat(Qt::PlainText);
  box.setObjectName(QStringLiteral("sessionFailedBox"));
  box.exec();
}

void MainWindow::onLevelDownload(int percent, const QString& name) {
  m_levelDownloading = percent >= 0;
  if (m_levelDownloading) {
    m_progressBar->setRange(0, 100);
    m_progressBar->setValue(percent);
    m_progressBar->setFormat(name + QStringLiteral(" %p%"));  // "Full detail 43%" (names hold no '%')
    m_progressBar->setToolTip(tr("Downloading %1 in the background; the shape stays live meanwhile").arg(name));
  }
  updateSessionActions();
}

void MainWindow::onProgress(int percent, const QString& what) {
  m_progressBar->setRange(0, 100);
  // The bar holds the percentage only (a long "what" was clipped in it); the message beside it says what.
  m_progressBar->setValue(percent);
  m_progressBar->setFormat(QStringLiteral("%p%"));
  m_progressBar->setToolTip(what);
  statusBar()->showMessage(what);
  updateSessionActions();
}

}  // namespace sc::app
