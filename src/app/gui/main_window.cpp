// MainWindow: construction and the file actions (open, export the deformed mesh, save a screenshot, open and save
// a session file, the Edit menu's undo/redo). The session wiring (menus, lock toolbar, status bar fields, docks,
// controller signals) is in main_window_session.cpp.

#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/gui/edit_actions.h"
#include "app/gui/host_controller.h"
#include "app/gui/host_dialog.h"
#include "app/gui/interactive_proxy.h"
#include "app/gui/mesh_summary.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/session_snapshot.h"
#include "app/gui/view_actions.h"
#include "model/mesh_loader.h"
#include "model/mesh_writer.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QImage>
#include <QKeySequence>
#include <QLabel>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QPainter>
#include <QStatusBar>

#include <filesystem>
#include <variant>

namespace sc::app {

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), ui(new Ui::MainWindow) {
  ui->setupUi(this);
  m_proxyBuilder = new InteractiveProxyBuilder(ui->viewport, this);
  m_meshSizeLabel = new QLabel(tr("No mesh"), this);
  m_meshSizeLabel->setObjectName(QStringLiteral("meshSizeLabel"));
  statusBar()->addPermanentWidget(m_meshSizeLabel);

  connect(ui->actionOpen, &QAction::triggered, this, &MainWindow::chooseAndOpenMesh);
  connect(ui->actionQuit, &QAction::triggered, this, &QWidget::close);
  connect(ui->actionResetView, &QAction::triggered, ui->viewport, &MeshViewport::resetView);

  // The session side (main_window_session.cpp), in this order: the docks bind to the drag history made before.
  setUpSessionControls();
  setUpSessionStatusBar();
  connectViewportToSession();
  setUpSessionDocks();
  setUpEditAndExport();
  setUpSessionFileActions();
  setUpSessionLife();
  setUpFiles();
  updateLockControls();
  setUpViewActions();
}

void MainWindow::setUpViewActions() {
  // Last: the View menu lists every dock and toolbar made above.
  m_viewActions =
      new ViewActions({this,
                       ui->viewport,
                       ui->menuView,
                       ui->actionResetView,
                       {ui->actionToolOrbit, ui->actionToolHandle, ui->actionToolAnchors, ui->actionToolDrag},
                       ui->sessionToolBar});
  // The up axis remembered for a file: a mesh opened, or the mesh or session file hosted.
  connect(this, &MainWindow::meshLoaded, m_viewActions,
          [this](const QString& path) { m_viewActions->showingFile(path); });
  connect(this, &MainWindow::sessionStarted, m_viewActions, [this](SessionController* controller) {
    const auto* host = qobject_cast<const HostController*>(controller);
    if (host == nullptr) return;
    connect(
        controller, &SessionController::displayLevelChanged, m_viewActions,
        [this, host] { m_viewActions->showingFile(host->settings().meshPath); }, Qt::SingleShotConnection);
  });
}

void MainWindow::setUpSessionFileActions() {
  // File → Open Session… / Save Session…, right after Open….
  auto* openAction = new QAction(tr("Open Sess&ion…"), this);
  openAction->setObjectName(QStringLiteral("actionOpenSession"));
  openAction->setStatusTip(tr("Host a saved session again (.shapecast: mesh, shape and undo history)"));
  auto* saveAction = new QAction(tr("Sa&ve Session…"), this);
  saveAction->setObjectName(QStringLiteral("actionSaveSession"));
  saveAction->setStatusTip(tr("Save the hosted session (mesh, shape and undo history) to host it again later"));
  saveAction->setShortcut(QKeySequence::Save);
  const QList<QAction*> fileActions = ui->menuFile->actions();
  const qsizetype openAt = fileActions.indexOf(ui->actionOpen);
  QAction* before = openAt >= 0 && openAt + 1 < fileActions.size() ? fileActions[openAt + 1] : nullptr;
  ui->menuFile->insertActions(before, {openAction, saveAction});
  connect(openAction, &QAction::triggered, this, &MainWindow::chooseAndOpenSession);
  connect(saveAction, &QAction::triggered, this, &MainWindow::chooseAndSaveSession);
  const auto updateEnabled = [this, saveAction] {
    saveAction->setEnabled(m_session != nullptr && m_session->role() == SessionController::Role::Host &&
                           m_session->state() == SessionController::State::Live);
  };
  connect(this, &MainWindow::sessionStarted, this, [this, updateEnabled](SessionController* controller) {
    connect(controller, &SessionController::stateChanged, this, updateEnabled);
    updateEnabled();
  });
  updateEnabled();
}

bool MainWindow::saveSession(const QString& path, QString* error) {
  const auto* host = qobject_cast<const HostController*>(m_session);
  if (host == nullptr) {
    if (error != nullptr) *error = tr("Only a live host can save its session.");
    return false;
  }
  return sc::app::saveSession(path, *host, error);
}

void MainWindow::chooseAndSaveSession() {
  const QString path =
      withSuffix(chooseFile({FileRequest::Kind::Save, tr("Save Session"), m_lastDirectory,
                             suggestedBaseName() + QStringLiteral(".") + QLatin1StringView(model::kSessionFileSuffix),
                             tr("ShapeCast session (*.shapecast)")}),
                 QLatin1StringView(model::kSessionFileSuffix));
  if (path.isEmpty()) return;
  QString error;
  if (saveSession(path, &error)) {
    rememberFile(path);
    statusBar()->showMessage(tr("Saved the session to %1").arg(QDir::toNativeSeparators(path)), kStatusMessageMs);
  } else {
    statusBar()->showMessage(error, kStatusMessageMs);
    if (m_errorDialogsEnabled) QMessageBox::warning(this, tr("Save Session"), error);
  }
}

void MainWindow::chooseAndOpenSession() {
  const QString path = chooseFile({FileRequest::Kind::Open,
                                   tr("Open Session"),
                                   m_lastDirectory,
                                   {},
                                   tr("ShapeCast sessions (*.shapecast);;All files (*)")});
  if (!path.isEmpty()) openSessionFile(path);
}

void MainWindow::setUpEditAndExport() {
  // Edit → Undo/Redo (the drag history), before the View menu.
  auto* editMenu = new QMenu(tr("&Edit"), this);
  editMenu->setObjectName(QStringLiteral("menuEdit"));
  editMenu->addAction(m_editActions->undoAction());
  editMenu->addAction(m_editActions->redoAction());
  menuBar()->insertMenu(ui->menuView->menuAction(), editMenu);
  addAction(m_editActions->undoAction());  // shortcuts work whichever widget has the focus
  addAction(m_editActions->redoAction());
  // File → Export Deformed Mesh… / Save Screenshot…, before Quit's separator.
  auto* exportAction = new QAction(tr("&Export Deformed Mesh…"), this);
  exportAction->setObjectName(QStringLiteral("actionExportMesh"));
  exportAction->setStatusTip(tr("Write the displayed mesh (this resolution, current shape) as OBJ or PLY"));
  auto* screenshotAction = new QAction(tr("Save &Screenshot…"), this);
  screenshotAction->setObjectName(QStringLiteral("actionSaveScreenshot"));
  screenshotAction->setStatusTip(tr("Save the 3D view as a PNG image"));
  const QList<QAction*> fileActions = ui->menuFile->actions();
  const qsizetype openAt = fileActions.indexOf(ui->actionOpen);
  QAction* before = openAt >= 0 && openAt + 1 < fileActions.size() ? fileActions[openAt + 1] : nullptr;
  ui->menuFile->insertActions(before, {exportAction, screenshotAction});
  connect(exportAction, &QAction::triggered, this, &MainWindow::chooseAndExportMesh);
  connect(screenshotAction, &QAction::triggered, this, &MainWindow::chooseAndSaveScreenshot);
  const auto updateEnabled = [this, exportAction, screenshotAction] {
    const bool hasMesh = ui->viewport->vertexCount() > 0;
    exportAction->setEnabled(hasMesh);
    screenshotAction->setEnabled(hasMesh);
  };
  connect(ui->viewport, &MeshViewport::meshChanged, this, updateEnabled);
  updateEnabled();
}

bool MainWindow::exportDeformedMesh(const QString& path, QString* error) {
  Eigen::MatrixXd V;
  const Eigen::MatrixXi* F = nullptr;
  // the session's current shape at this peer's resolution: the CPU kernel on the shared level and frame
  const std::vector<float> positions = m_session != nullptr ? m_session->positions() : std::vector<float>();
  if (!positions.empty() && m_session->displayFaces().rows() > 0 &&
      positions.size() == static_cast<std::size_t>(m_session->displayRestPositions().rows()) * 3) {
    V.resize(static_cast<Eigen::Index>(positions.size() / 3), 3);
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      for (Eigen::Index c = 0; c < 3; ++c) V(i, c) = positions[static_cast<std::size_t>(3 * i + c)];
    }
    F = &m_session->displayFaces();
  } else if (m_openedV.rows() > 0) {
    V = m_openedV;
    F = &m_openedF;
  } else {
    if (error != nullptr) *error = tr("There is no mesh to export.");
    return false;
  }
  const QString suffix = QFileInfo(path).suffix().toLower();
  if (suffix != QStringLiteral("obj") && suffix != QStringLiteral("ply")) {
    if (error != nullptr) *error = tr("Export writes OBJ or PLY files: %1").arg(path);
    return false;
  }
  const std::optional<model::MeshWriteError> failure =
      model::writeMesh(std::filesystem::path(QFile::encodeName(path).toStdString()), V, *F);
  if (failure) {
    if (error != nullptr) *error = QString::fromStdString(failure->message);
    return false;
  }
  return true;
}

bool MainWindow::saveScreenshot(const QString& path, QString* error) {
  const QImage image = ui->viewport->grabFramebuffer();
  if (image.isNull() || !image.save(path, "PNG")) {
    if (error != nullptr) *error = tr("Could not save the screenshot to %1").arg(path);
    return false;
  }
  return true;
}

QImage MainWindow::grabWindow() {
  QImage image = grab().toImage();
  const QImage view = ui->viewport->grabFramebuffer();
  if (!image.isNull() && !view.isNull() && ui->viewport->isVisible()) {
    QPainter painter(&image);
    painter.drawImage(QRect(ui->viewport->mapTo(this, QPoint(0, 0)), ui->viewport->size()), view);
  }
  return image;
}

void MainWindow::chooseAndExportMesh() {
  QString selectedFilter;
  QString path = chooseFile(
      {FileRequest::Kind::Save, tr("Export Deformed Mesh"), m_lastDirectory,
       suggestedBaseName() + QStringLiteral("-deformed.obj"), tr("Wavefront OBJ (*.obj);;Stanford PLY (*.ply)")},
      &selectedFilter);
  if (path.isEmpty()) return;
  path =
      withSuffix(path, selectedFilter.contains(QStringLiteral("ply")) ? QStringLiteral("ply") : QStringLiteral("obj"));
  QString error;
  if (exportDeformedMesh(path, &error)) {
    statusBar()->showMessage(tr("Exported %1").arg(QDir::toNativeSeparators(path)), kStatusMessageMs);
  } else {
    statusBar()->showMessage(error, kStatusMessageMs);
    if (m_errorDialogsEnabled) QMessageBox::warning(this, tr("Export"), error);
  }
}

void MainWindow::chooseAndSaveScreenshot() {
  const QString path = withSuffix(chooseFile({FileRequest::Kind::Save, tr("Save Screenshot"), m_lastDirectory,
                                              suggestedBaseName() + QStringLiteral(".png"), tr("PNG image (*.png)")}),
                                  QStringLiteral("png"));
  if (path.isEmpty()) return;
  QString error;
  if (saveScreenshot(path, &error)) {
    statusBar()->showMessage(tr("Saved %1").arg(QDir::toNativeSeparators(path)), kStatusMessageMs);
  } else {
    statusBar()->showMessage(error, kStatusMessageMs);
    if (m_errorDialogsEnabled) QMessageBox::warning(this, tr("Screenshot"), error);
  }
}

MainWindow::~MainWindow() {
  // The session (a child) outlives ui: its leave() on destruction emits signals that would reach this half-destroyed
  // window (a joined client's window closing used to crash here).
  if (m_pendingJoin != nullptr) m_pendingJoin->disconnect(this);
  if (m_session != nullptr) {
    m_session->disconnect(this);
    m_session->leave();
  }
  delete ui;
}

MeshViewport* MainWindow::viewport() const { return ui->viewport; }

bool MainWindow::openMesh(const QString& path) {
  const std::filesystem::path file(QFile::encodeName(path).toStdString());
  model::MeshLoadResult result = model::loadMesh(file);

  if (const auto* error = std::get_if<model::MeshError>(&result)) {
    const QString message = QString::fromStdString(error->message);
    emit loadFailed(path, message);
    if (m_errorDialogsEnabled) {
      QMessageBox::critical(this, tr("Could not open mesh"), message);
    }
    return false;
  }
  showMesh(path, std::get<model::LoadedMesh>(result));
  return true;
}

void MainWindow::showMesh(const QString& path, const model::LoadedMesh& mesh) {
  // Never show another mesh in a live session (its handles, anchors and drags would go to the hosted model): the
  // session ends first (File → Open… asks before: openMeshAsking()).
  if (sessionActive()) leaveSession();
  ui->viewport->setMesh(mesh.V, mesh.F);
  m_proxyBuilder->build(mesh.V, mesh.F);
  m_openedV = mesh.V;
  m_openedF = mesh.F;
  const int vertexCount = static_cast<int>(mesh.V.rows());
  const int triangleCount = static_cast<int>(mesh.F.rows());
  m_meshSizeLabel->setText(meshSizeText(vertexCount, triangleCount));
  statusBar()->showMessage(cleaningSummary(mesh.cleaning), kStatusMessageMs);
  m_openedPath = path;
  rememberFile(path);
  setWindowTitle(QFileInfo(path).fileName() + QStringLiteral(" — ShapeCast"));
  emit meshLoaded(path, vertexCount, triangleCount);
}

void MainWindow::chooseAndOpenMesh() {
  const QString path = chooseFile({FileRequest::Kind::Open,
                                   tr("Open Mesh"),
                                   m_lastDirectory,
                                   {},
                                   tr("Meshes (*.off *.obj *.ply *.stl *.OFF *.OBJ *.PLY *.STL);;ShapeCast sessions "
                                      "(*.shapecast);;All files (*)")});
  if (!path.isEmpty()) openFileFromUser(path);
}

}  // namespace sc::app
