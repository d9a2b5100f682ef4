// MainWindow: the session wiring. Session menu, tool actions, lock toolbar and resolution selector, status bar
// fields, viewport intents to the SessionController, the docks; and the controller's signals back to the window
// (the frame path: its level and frames straight to the viewport).

#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/gui/edit_actions.h"
#include "app/gui/host_controller.h"
#include "app/gui/host_dialog.h"
#include "app/gui/interactive_proxy.h"
#include "app/gui/join_dialog.h"
#include "app/gui/mesh_summary.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/network_conditions_dock.h"
#include "app/gui/session_docks.h"
#include "app/gui/session_identity_view.h"
#include "app/gui/session_presence.h"
#include "app/gui/vertex_id_lists.h"
#include "model/session_file.h"

#include <QActionGroup>
#include <QComboBox>
#include <QFileInfo>
#include <QLabel>
#include <QMessageBox>
#include <QProgressBar>
#include <QStatusBar>
#include <QToolBar>
#include <QToolButton>

#include <optional>
#include <utility>

namespace sc::app {

// Session menu, tools, lock toolbar, resolution selector.
void MainWindow::setUpSessionControls() {
  connect(ui->actionHostSession, &QAction::triggered, this, &MainWindow::showHostDialog);
  connect(ui->actionJoinSession, &QAction::triggered, this, &MainWindow::showJoinDialog);
  connect(ui->actionLeaveSession, &QAction::triggered, this, &MainWindow::leaveSessionAsking);
  auto* tools = new QActionGroup(this);
  const std::pair<QAction*, ViewportTool> toolActions[] = {{ui->actionToolOrbit, ViewportTool::Orbit},
                                                           {ui->actionToolHandle, ViewportTool::HandleBrush},
                                                           {ui->actionToolAnchors, ViewportTool::AnchorBrush},
                                                           {ui->actionToolDrag, ViewportTool::Drag}};
  for (const auto& [action, tool] : toolActions) {
    tools->addAction(action);
    connect(action, &QAction::triggered, ui->viewport, [this, chosen = tool] { ui->viewport->setTool(chosen); });
  }
  m_lockLabel = new QLabel(this);
  m_lockLabel->setObjectName(QStringLiteral("lockLabel"));
  m_lockLabel->setContentsMargins(6, 0, 6, 0);
  ui->sessionToolBar->addWidget(m_lockLabel);
  ui->sessionToolBar->addSeparator();
  m_levelCombo = new QComboBox(this);
  m_levelCombo->setObjectName(QStringLiteral("levelCombo"));
  m_levelCombo->setToolTip(tr("Display resolution: switching keeps the current deformation"));
  m_levelCombo->setEnabled(false);
  m_levelCombo->setSizeAdjustPolicy(QComboBox::AdjustToContents);
  ui->sessionToolBar->addWidget(m_levelCombo);
  // The host's certificate fingerprint (docs/security.md): a toolbar button and Session ▸ Session info….
  const auto showSessionInfo = [this] {
    auto* dialog = new SessionInfoDialog(sessionActive() ? m_session : nullptr, this);
    dialog->setAttribute(Qt::WA_DeleteOnClose);
    dialog->show();
  };
  auto* identity = new HostIdentityButton(this);
  QAction* identityAction = ui->sessionToolBar->addWidget(identity);
  identityAction->setVisible(false);
  connect(identity, &HostIdentityButton::shownChanged, identityAction, &QAction::setVisible);
  connect(identity, &QToolButton::clicked, this, showSessionInfo);
  connect(this, &MainWindow::sessionStarted, identity, &HostIdentityButton::bind);
  connect(this, &MainWindow::sessionEnded, identity, [identity] { identity->bind(nullptr); });
  QAction* infoAction = ui->menuSession->addAction(tr("Session &Info…"));
  infoAction->setObjectName(QStringLiteral("actionSessionInfo"));
  connect(infoAction, &QAction::triggered, this, showSessionInfo);
  connect(ui->actionLock, &QAction::triggered, this, [this] {
    if (m_session == nullptr) return;
    if (m_session->lockWanted()) {
      m_session->releaseLock();
    } else {
      m_session->requestLock();
    }
    updateLockControls();
  });
  connect(m_levelCombo, &QComboBox::activated, this, [this](int index) {
    if (m_session != nullptr) m_session->setLevel(m_levelCombo->itemData(index).toUInt());
  });
}

// Status bar fields of a session: frame timing, progress of a preparation or connection, its Cancel button.
void MainWindow::setUpSessionStatusBar() {
  m_timingLabel = new QLabel(this);
  m_timingLabel->setObjectName(QStringLiteral("frameTimeLabel"));
  statusBar()->addPermanentWidget(m_timingLabel);
  m_progressBar = new QProgressBar(this);
  m_progressBar->setObjectName(QStringLiteral("sessionProgress"));
  m_progressBar->setRange(0, 100);
  m_progressBar->setMaximumWidth(180);
  m_progressBar->hide();
  statusBar()->addPermanentWidget(m_progressBar);
  m_cancelButton = new QToolButton(this);
  m_cancelButton->setText(tr("Cancel"));
  m_cancelButton->hide();
  statusBar()->addPermanentWidget(m_cancelButton);
  connect(m_cancelButton, &QToolButton::clicked, this, [this] {
    if (meshLoadRunning()) {
      cancelMeshLoading();  // a mesh being read (main_window_files.cpp): the session is not the one to stop
    } else if (m_pendingJoin != nullptr) {
      m_pendingJoin->cancel();  // the session we are in goes on
    } else if (m_session != nullptr) {
      m_session->cancel();
    }
  });
}

void MainWindow::connectViewportToSession() {
  // Viewport intents → session. Handle/anchor strokes send constraints, drags send poses (the controller checks
  // the lock; the viewport blocks drags itself through setDragAllowed()). The viewport's plain ids are displayed
  // vertex ids: typed here, where the two meet.
  connect(ui->viewport, &MeshViewport::handlePainted, this, [this](const std::vector<int>& handles) {
    if (m_session != nullptr) m_session->setHandle(typedIds<spectral::DisplayVertexId>(handles));
  });
  connect(ui->viewport, &MeshViewport::anchorsPainted, this, [this](const std::vector<int>& anchors) {
    if (m_session != nullptr) m_session->setAnchors(typedIds<spectral::DisplayVertexId>(anchors));
  });
  // Each drag is a stroke: its end makes it an edit step of the session's shared history (Edit menu).
  m_editActions = new EditActions(this);
  connect(ui->viewport, &MeshViewport::dragStarted, this, [this] {
    if (m_session != nullptr && m_session->beginDrag()) m_editActions->refresh();
  });
  connect(ui->viewport, &MeshViewport::dragMoved, this,
          [this](const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation) {
            if (m_session != nullptr) m_session->dragTo(translation, rotation);
          });
  connect(ui->viewport, &MeshViewport::dragFinished, this, [this] {
    if (m_session == nullptr) return;
    m_session->endDrag();
    m_editActions->refresh();
  });
  connect(ui->viewport, &MeshViewport::frameSwapped, this, [this] {
    const FrameTimes& frame = ui->viewport->frameTimes();
    if (m_redrawPending) {
      m_redrawPending = false;
      // As shapecast-bench-viewport: the viewport's own reconstruction, normals, paint and composition.
      m_viewReconstructMs = frame.reconstructMs;
      m_redrawMs = frame.totalMs() - frame.reconstructMs;
    } else if (frame.triangles == m_labelFrame.triangles && frame.renderScale == m_labelFrame.renderScale) {
      return;  // e.g. the idle full redraw after a moving frame changes the label's "moving" part
    }
    updateTimingLabel();
  });
}

void MainWindow::setUpSessionDocks() {
  // Peers and statistics docks follow whichever session is current.
  m_docks = new SessionDocks(this);
  connect(this, &MainWindow::sessionStarted, m_docks, &SessionDocks::bind);
  m_presence = new SessionPresence(ui->viewport, m_docks->peersDock(), this);
  connect(this, &MainWindow::sessionStarted, m_presence, &SessionPresence::bind);
  // Network conditions (emulated loss, burst, delay) of a client, under the other docks; View menu toggles it.
  m_networkDock = new NetworkConditionsDock(this);
  addDockWidget(Qt::RightDockWidgetArea, m_networkDock);
  ui->menuView->addAction(m_networkDock->toggleViewAction());
  connect(this, &MainWindow::sessionStarted, m_networkDock, &NetworkConditionsDock::bind);
  connect(this, &MainWindow::sessionStarted, m_editActions, &EditActions::bind);
  connect(this, &MainWindow::sessionStarted, this, [this](SessionController* controller) {
    if (controller == nullptr) return;
    connect(controller, &SessionController::savedSessionRestored, this, [this, controller] {
      showSessionSelection();
      ui->viewport->resetView();  // frame the restored shape: the level was framed at rest
      const model::SessionFile* saved = controller->savedSession();
      if (saved != nullptr && saved->droppedLegacyDrags > 0) {
        statusBar()->showMessage(tr("This session was saved by an older ShapeCast: its shape is restored, its undo "
                                    "history of %n drag(s) is not.",
                                    nullptr, saved->droppedLegacyDrags),
                                 kStatusMessageMs);
      }
    });
  });
}

// ---------------------------------------------------------------------------------------------------- sessions

void MainWindow::showHostDialog() {
  HostDialog dialog(this);
  if (dialog.exec() == QDialog::Accepted) hostSession(dialog.settings());
}

void MainWindow::showJoinDialog() {
  JoinDialog dialog(this);
  if (dialog.exec() == QDialog::Accepted) joinSession(dialog.settings());
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
  ui->viewport->setDisplayLevel(level);
  if (level) m_proxyBuilder->build(level->level.restV, level->level.F);
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
