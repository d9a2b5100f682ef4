#include "app/gui/main_window.h"

#include "ui_main_window.h"

#include "app/gui/mesh_summary.h"
#include "app/gui/mesh_viewport.h"
#include "model/mesh_loader.h"

#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMessageBox>
#include <QStatusBar>

#include <filesystem>
#include <variant>

namespace sc::app {

namespace {
constexpr int kCleaningMessageMs = 10000;
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), ui(new Ui::MainWindow) {
  ui->setupUi(this);
  m_meshSizeLabel = new QLabel(tr("No mesh"), this);
  m_meshSizeLabel->setObjectName(QStringLiteral("meshSizeLabel"));
  statusBar()->addPermanentWidget(m_meshSizeLabel);

  connect(ui->actionOpen, &QAction::triggered, this, &MainWindow::chooseAndOpenMesh);
  connect(ui->actionQuit, &QAction::triggered, this, &QWidget::close);
  connect(ui->actionResetView, &QAction::triggered, ui->viewport, &MeshViewport::resetView);
}

MainWindow::~MainWindow() { delete ui; }

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

  const auto& mesh = std::get<model::LoadedMesh>(result);
  ui->viewport->setMesh(mesh.V, mesh.F);
  const int vertexCount = static_cast<int>(mesh.V.rows());
  const int triangleCount = static_cast<int>(mesh.F.rows());
  m_meshSizeLabel->setText(meshSizeText(vertexCount, triangleCount));
  statusBar()->showMessage(cleaningSummary(mesh.cleaning), kCleaningMessageMs);
  const QFileInfo info(path);
  m_lastDirectory = info.absolutePath();
  setWindowTitle(info.fileName() + QStringLiteral(" — ShapeCast"));
  emit meshLoaded(path, vertexCount, triangleCount);
  return true;
}

void MainWindow::chooseAndOpenMesh() {
  const QString path =
      QFileDialog::getOpenFileName(this, tr("Open Mesh"), m_lastDirectory,
                                   tr("Meshes (*.off *.obj *.ply *.stl *.OFF *.OBJ *.PLY *.STL);;All files (*)"));
  if (!path.isEmpty()) {
    openMesh(path);
  }
}

}  // namespace sc::app
