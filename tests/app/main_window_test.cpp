// Tests for src/app/gui/main_window.cpp: loading through the window, errors reported without crashing.

#include "app/gui/main_window.h"

#include "app/gui/mesh_viewport.h"
#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QLabel>
#include <QMessageBox>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTimer>

namespace {

QString meshSizeLabelText(const sc::app::MainWindow& window) {
  const auto* label = window.findChild<QLabel*>(QStringLiteral("meshSizeLabel"));
  return label != nullptr ? label->text() : QStringLiteral("<no meshSizeLabel>");
}

}  // namespace

TEST(MainWindow, MissingFileEmitsLoadFailed) {
  sc::app::MainWindow window;
  window.setErrorDialogsEnabled(false);
  QSignalSpy failed(&window, &sc::app::MainWindow::loadFailed);
  QSignalSpy loaded(&window, &sc::app::MainWindow::meshLoaded);
  const QString path = QStringLiteral("/nonexistent/folder/missing_mesh.off");
  EXPECT_FALSE(window.openMesh(path));
  ASSERT_EQ(failed.count(), 1);
  EXPECT_EQ(loaded.count(), 0);
  EXPECT_EQ(failed.at(0).at(0).toString(), path);
  const QString message = failed.at(0).at(1).toString();
  EXPECT_FALSE(message.isEmpty());
  EXPECT_TRUE(message.contains(QStringLiteral("missing_mesh.off"))) << message.toStdString();
  EXPECT_EQ(window.viewport()->vertexCount(), 0);
  EXPECT_EQ(meshSizeLabelText(window), QStringLiteral("No mesh"));
}

TEST(MainWindow, MissingFileShowsAMessageBoxWhenDialogsAreEnabled) {
  sc::app::MainWindow window;
  ASSERT_TRUE(window.errorDialogsEnabled());
  QString boxText;
  QTimer closer;
  QObject::connect(&closer, &QTimer::timeout, [&boxText] {
    if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
      boxText = box->text();
      box->accept();
    }
  });
  closer.start(50);
  EXPECT_FALSE(window.openMesh(QStringLiteral("/nonexistent/missing_mesh.ply")));
  closer.stop();
  EXPECT_TRUE(boxText.contains(QStringLiteral("missing_mesh.ply"))) << boxText.toStdString();
}

TEST(MainWindow, OpensAGeneratedOffFile) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString path = dir.filePath(QStringLiteral("sphere.off"));
  const auto sphere = sc::testing::icosphere(3);
  ASSERT_TRUE(sc::testing::writeOff(path, sphere.V, sphere.F));

  sc::app::MainWindow window;
  window.setErrorDialogsEnabled(false);
  QSignalSpy loaded(&window, &sc::app::MainWindow::meshLoaded);
  ASSERT_TRUE(window.openMesh(path));
  ASSERT_EQ(loaded.count(), 1);
  EXPECT_EQ(loaded.at(0).at(1).toInt(), 642);
  EXPECT_EQ(loaded.at(0).at(2).toInt(), 1280);
  EXPECT_EQ(window.viewport()->vertexCount(), 642);
  EXPECT_EQ(window.viewport()->triangleCount(), 1280);
  EXPECT_EQ(meshSizeLabelText(window), QStringLiteral("642 vertices, 1280 triangles"));
  EXPECT_TRUE(window.statusBar()->currentMessage().startsWith(QStringLiteral("Mesh is clean.")))
      << window.statusBar()->currentMessage().toStdString();
  EXPECT_TRUE(window.windowTitle().contains(QStringLiteral("sphere.off")));

  // A failed load afterwards keeps the mesh that is shown.
  EXPECT_FALSE(window.openMesh(dir.filePath(QStringLiteral("absent.off"))));
  EXPECT_EQ(window.viewport()->vertexCount(), 642);
  EXPECT_EQ(meshSizeLabelText(window), QStringLiteral("642 vertices, 1280 triangles"));
}
