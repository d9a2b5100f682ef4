// MainWindow: files (issue 16). Drops of meshes and session files on the window, File → Open Recent, the file
// questions (the folder last used, a suggested name), and meshes read on a worker thread with progress and Cancel
// in the status bar (MeshLoading). Everything goes through openFileFromUser(), as File → Open… does.

#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/gui/host_controller.h"
#include "app/gui/host_dialog.h"
#include "app/gui/mesh_loading.h"
#include "app/gui/recent_files.h"
#include "model/mesh_loader.h"
#include "model/session_file.h"

#include <QAction>
#include <QDir>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileInfo>
#include <QMenu>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QSettings>
#include <QStatusBar>
#include <QUrl>

namespace sc::app {

namespace {

/// The first local file of a drag, or empty.
QString droppedFile(const QMimeData* mime) {
  if (mime == nullptr || !mime->hasUrls()) return {};
  for (const QUrl& url : mime->urls()) {
    if (url.isLocalFile()) return url.toLocalFile();
  }
  return {};
}

}  // namespace

void MainWindow::setUpFiles() {
  setAcceptDrops(true);
  QSettings settings;
  m_lastDirectory = RecentFiles::load(settings).folder;
  // File → Open Recent, after Open Session…
  m_recentMenu = new QMenu(tr("Open &Recent"), this);
  m_recentMenu->setObjectName(QStringLiteral("menuOpenRecent"));
  auto* openSession = findChild<QAction*>(QStringLiteral("actionOpenSession"));
  const QList<QAction*> fileActions = ui->menuFile->actions();
  const qsizetype at = fileActions.indexOf(openSession);
  QAction* before = at >= 0 && at + 1 < fileActions.size() ? fileActions[at + 1] : nullptr;
  ui->menuFile->insertMenu(before, m_recentMenu);
  connect(m_recentMenu, &QMenu::aboutToShow, this, &MainWindow::rebuildRecentMenu);
  rebuildRecentMenu();
}

void MainWindow::rebuildRecentMenu() {
  QSettings settings;
  RecentFiles recent = RecentFiles::load(settings);
  const QStringList missing = recent.dropMissing();
  if (!missing.isEmpty()) {
    recent.save(settings);
    statusBar()->showMessage(
        tr("No longer there, removed from Open Recent: %1").arg(missing.join(QStringLiteral(", "))), kStatusMessageMs);
  }
  m_recentMenu->clear();
  for (const QString& path : recent.paths) {
    QAction* action = m_recentMenu->addAction(QFileInfo(path).fileName());
    action->setToolTip(QDir::toNativeSeparators(path));
    action->setStatusTip(QDir::toNativeSeparators(path));
    action->setData(path);
    connect(action, &QAction::triggered, this, [this, path] { openFileFromUser(path); });
  }
  m_recentMenu->setEnabled(!recent.paths.isEmpty());
}

QStringList MainWindow::recentFiles() const {
  QSettings settings;
  return RecentFiles::load(settings).paths;
}

void MainWindow::rememberFile(const QString& path) {
  QSettings settings;
  RecentFiles recent = RecentFiles::load(settings);
  recent.remember(path);
  recent.save(settings);
  m_lastDirectory = recent.folder;
  rebuildRecentMenu();
}

QString MainWindow::chooseFile(const FileRequest& request, QString* selectedFilter) {
  const QString path =
      m_fileChooser ? m_fileChooser(request, selectedFilter) : chooseInFileDialog(this, request, selectedFilter);
  if (!path.isEmpty()) {
    m_lastDirectory = QFileInfo(path).absolutePath();
    QSettings settings;
    RecentFiles recent = RecentFiles::load(settings);
    recent.folder = m_lastDirectory;
    recent.save(settings);
  }
  return path;
}

QString MainWindow::suggestedBaseName() const {
  const auto* host = qobject_cast<const HostController*>(m_session);
  const QString source = host != nullptr ? host->settings().meshPath : m_openedPath;
  const QString base = QFileInfo(source).completeBaseName();
  return base.isEmpty() ? QStringLiteral("shapecast") : base;
}

// ---------------------------------------------------------------------------------------------------- opening

bool MainWindow::openFileFromUser(const QString& path) {
  if (!QFileInfo::exists(path)) {
    const QString message = tr("%1 is no longer there.").arg(QDir::toNativeSeparators(path));
    QSettings settings;
    RecentFiles recent = RecentFiles::load(settings);
    if (recent.paths.removeAll(QFileInfo(path).absoluteFilePath()) > 0) recent.save(settings);
    rebuildRecentMenu();
    statusBar()->showMessage(message, kStatusMessageMs);
    emit loadFailed(path, message);
    if (m_errorDialogsEnabled) QMessageBox::warning(this, tr("Open"), message);
    return false;
  }
  if (model::isSessionFile(path)) return openSessionFile(path);
  return openMeshAsking(path, MeshLoad::Background);
}

bool MainWindow::openSessionFile(const QString& path) {
  // The Host dialog with this file: port, password and name are still the user's to choose.
  HostDialog dialog(this);
  HostSettings settings = dialog.settings();
  settings.meshPath = path;
  dialog.setSettings(settings);
  if (dialog.exec() != QDialog::Accepted) return false;
  rememberFile(path);
  return hostSession(dialog.settings());
}

void MainWindow::loadMeshInBackground(const QString& path) {
  cancelMeshLoading();
  auto* loading = new MeshLoading(this);
  m_meshLoading = loading;
  connect(loading, &MeshLoading::progress, this, [this](int percent, const QString& what) {
    m_progressBar->setRange(0, 0);  // the reader says nothing until it is done: busy
    m_progressBar->setFormat(what);
    statusBar()->showMessage(what);
    static_cast<void>(percent);
    updateSessionActions();
  });
  connect(loading, &MeshLoading::loaded, this,
          [this](const QString& loadedPath, const std::shared_ptr<const model::LoadedMesh>& mesh) {
            m_meshLoading = nullptr;
            m_progressBar->setRange(0, 100);
            showMesh(loadedPath, *mesh);
            updateSessionActions();
          });
  connect(loading, &MeshLoading::failed, this, [this](const QString& failedPath, const QString& message) {
    m_meshLoading = nullptr;
    m_progressBar->setRange(0, 100);
    updateSessionActions();
    statusBar()->showMessage(message, kStatusMessageMs);
    emit loadFailed(failedPath, message);
    if (m_errorDialogsEnabled) QMessageBox::critical(this, tr("Could not open mesh"), message);
  });
  connect(loading, &MeshLoading::cancelled, this, [this](const QString& cancelledPath) {
    m_meshLoading = nullptr;
    m_progressBar->setRange(0, 100);
    updateSessionActions();
    statusBar()->showMessage(tr("Stopped opening %1: nothing changed.").arg(QFileInfo(cancelledPath).fileName()),
                             kStatusMessageMs);
    emit loadCancelled(cancelledPath);
  });
  loading->start(path);
}

void MainWindow::cancelMeshLoading() {
  if (m_meshLoading) m_meshLoading->cancel();
}

bool MainWindow::meshLoadRunning() const { return m_meshLoading && m_meshLoading->running(); }

// ---------------------------------------------------------------------------------------------------- drops

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (!droppedFile(event->mimeData()).isEmpty()) {
    event->acceptProposedAction();
  } else {
    QMainWindow::dragEnterEvent(event);
  }
}

void MainWindow::dropEvent(QDropEvent* event) {
  const QString path = droppedFile(event->mimeData());
  if (path.isEmpty()) {
    QMainWindow::dropEvent(event);
    return;
  }
  event->acceptProposedAction();
  // After the drop returns: the questions and dialogs it may open must not run inside the drag.
  QMetaObject::invokeMethod(
      this, [this, path] { openFileFromUser(path); }, Qt::QueuedConnection);
}

}  // namespace sc::app
