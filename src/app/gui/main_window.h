#pragma once
// MainWindow: the application window. Wiring only: menus → mesh loading (sc::model) → MeshViewport and status bar.

#include <QMainWindow>
#include <QString>

class QLabel;

namespace Ui {
class MainWindow;
}

namespace sc::app {

class MeshViewport;

/// The ShapeCast main window: File → Open…/Quit, View → Reset View, a MeshViewport as central widget and a status
/// bar with the mesh size (permanent, objectName "meshSizeLabel") and, briefly, the cleaning report.
class MainWindow : public QMainWindow {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MainWindow)

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Loads a mesh file with sc::model::loadMesh() and shows it. Never throws.
  /// On success emits meshLoaded() and returns true. On failure keeps the current mesh, emits loadFailed() with
  /// the loader's message, shows it in a modal QMessageBox if error dialogs are enabled, and returns false.
  bool openMesh(const QString& path);

  /// Whether load errors also open a modal message box (default true). Off for tests and --screenshot runs,
  /// which observe loadFailed() instead.
  void setErrorDialogsEnabled(bool enabled) { m_errorDialogsEnabled = enabled; }
  [[nodiscard]] bool errorDialogsEnabled() const { return m_errorDialogsEnabled; }

  [[nodiscard]] MeshViewport* viewport() const;

 signals:
  /// A mesh was loaded from path and is shown.
  void meshLoaded(const QString& path, int vertexCount, int triangleCount);
  /// Loading path failed; message names the file and the problem.
  void loadFailed(const QString& path, const QString& message);

 private slots:
  void chooseAndOpenMesh();

 private:
  Ui::MainWindow* ui;
  QLabel* m_meshSizeLabel = nullptr;
  QString m_lastDirectory;
  bool m_errorDialogsEnabled = true;
};

}  // namespace sc::app
