// MainWindow: the session wiring set up once: Session menu, tool actions, lock toolbar and resolution selector,
// status bar fields, viewport intents to the SessionController, and the docks that follow the current session.

#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/gui/edit_actions.h"
#include "app/gui/interactive_proxy.h"
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
#include <QLabel>
#include <QProgressBar>
#include <QStatusBar>
#include <QToolBar>
#include <QToolButton>

#include <cstdio>

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
    if (m_installPaintPending) {
      m_installPaintPending = false;
      std::fprintf(
          stderr,
          "shapecast: first paint of the level: upload %.1f ms, background %.1f ms, mesh %.1f ms (%d "
          "triangles%s), compose %.1f ms\n",
          frame.uploadMs, frame.backgroundMs, frame.meshMs, frame.triangles,
          frame.pictureSlices > 0
              ? qPrintable(QStringLiteral(", a progressive picture of %1 slice(s) so far").arg(frame.pictureSlices))
              : "",
          frame.composeMs);
    }
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

}  // namespace sc::app
