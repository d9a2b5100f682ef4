// The window's files (issue 16): drops of meshes on the window, File → Open Recent (QSettings, missing files
// dropped with a message), Ctrl+S for Save Session with a suggested name in the last folder, and meshes read on a
// worker thread whose Cancel, or a broken file, keeps the mesh and the session the window had.

#include "app/gui/main_window.h"
#include "app/gui/recent_files.h"
#include "app/gui/recent_sessions.h"
#include "app_test_support.h"
#include "session_windows.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QDir>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileInfo>
#include <QKeySequence>
#include <QMenu>
#include <QMimeData>
#include <QProgressBar>
#include <QSettings>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTest>
#include <QToolButton>
#include <QUrl>

#include <vector>

namespace sc::app {
namespace {

using State = SessionController::State;

class WindowFilesTest : public sc::testing::TorusSessionTest {
 protected:
  void SetUp() override {
    sc::testing::TorusSessionTest::SetUp();
    if (IsSkipped()) return;
    QSettings().remove(QStringLiteral("files"));  // this test process's settings (test_main.cpp)
    m_sphere = sc::testing::icosphere(1);
    m_spherePath = m_dir.filePath(QStringLiteral("sphere.off"));
    ASSERT_TRUE(sc::testing::writeOff(m_spherePath, m_sphere.V, m_sphere.F));
  }
  void TearDown() override { QSettings().remove(QStringLiteral("files")); }
  /// A window shown, its questions answered without modal boxes.
  void show(MainWindow& window) { sc::testing::showSessionWindow(window, QSize(480, 360)); }
  [[nodiscard]] QString brokenFile() const {
    const QString path = m_dir.filePath(QStringLiteral("broken.off"));
    QFile file(path);
    EXPECT_TRUE(file.open(QIODevice::WriteOnly));
    file.write("OFF\n4 2 0\n0 0 0\n1 0 0\n");  // cut short: 2 of 4 vertices, no faces
    return path;
  }
  static QToolButton* cancelButton(const MainWindow& window) {
    for (QToolButton* button : window.statusBar()->findChildren<QToolButton*>()) {
      if (button->text() == QStringLiteral("Cancel")) return button;
    }
    return nullptr;
  }
  static void drop(MainWindow& window, const QString& path, bool* accepted) {
    QMimeData mime;
    mime.setUrls({QUrl::fromLocalFile(path)});
    QDragEnterEvent enter(QPoint(20, 20), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QCoreApplication::sendEvent(&window, &enter);
    *accepted = enter.isAccepted();
    QDropEvent dropped(QPointF(20, 20), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QCoreApplication::sendEvent(&window, &dropped);
  }

  sc::testing::GeneratedMesh m_sphere;
  QString m_spherePath;
};

TEST(RecentFilesList, MostRecentFirstAtMostTenAndMissingOnesDropped) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  RecentFiles recent;
  for (int i = 0; i < 12; ++i) {
    const QString path = dir.filePath(QStringLiteral("m%1.off").arg(i));
    QFile file(path);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    recent.remember(path);
  }
  recent.remember(dir.filePath(QStringLiteral("m5.off")));
  ASSERT_EQ(recent.paths.size(), kMaxRecentEntries);
  EXPECT_EQ(recent.paths.front(), dir.filePath(QStringLiteral("m5.off")));
  EXPECT_EQ(recent.paths.at(1), dir.filePath(QStringLiteral("m11.off")));
  EXPECT_EQ(recent.paths.count(dir.filePath(QStringLiteral("m5.off"))), 1);
  EXPECT_EQ(recent.folder, QFileInfo(dir.path()).absoluteFilePath());
  ASSERT_TRUE(QFile::remove(dir.filePath(QStringLiteral("m11.off"))));
  EXPECT_EQ(recent.dropMissing(), QStringList{dir.filePath(QStringLiteral("m11.off"))});
  EXPECT_EQ(recent.paths.size(), kMaxRecentEntries - 1);
}

TEST_F(WindowFilesTest, DroppedMeshOpensAsFileOpenDoes) {
  MainWindow window;
  show(window);
  QSignalSpy loaded(&window, &MainWindow::meshLoaded);
  bool accepted = false;
  drop(window, m_spherePath, &accepted);
  EXPECT_TRUE(accepted);
  ASSERT_TRUE(QTest::qWaitFor([&] { return loaded.count() == 1; }, 10000));
  EXPECT_EQ(loaded.front().at(0).toString(), m_spherePath);
  EXPECT_EQ(window.viewport()->vertexCount(), static_cast<int>(m_sphere.V.rows()));
  EXPECT_TRUE(window.windowTitle().startsWith(QStringLiteral("sphere.off")));
  EXPECT_EQ(window.recentFiles().value(0), QFileInfo(m_spherePath).absoluteFilePath());
}

TEST_F(WindowFilesTest, DropWhileHostingAsksFirst) {
  MainWindow window;
  show(window);
  HostController* hosting = sc::testing::hostAndWait(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  const int hosted = window.viewport()->vertexCount();
  std::vector<SessionQuestion> asked;
  window.setSessionAsker([&](const SessionQuestion& question) {
    asked.push_back(question);
    return SessionAnswer::Cancel;
  });
  bool accepted = false;
  drop(window, m_spherePath, &accepted);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !asked.empty(); }, 5000));
  EXPECT_EQ(asked[0].text, QStringLiteral("You are hosting torus.off. Open sphere.off:"));
  EXPECT_EQ(hosting->state(), State::Live);
  EXPECT_EQ(window.viewport()->vertexCount(), hosted);
}

TEST_F(WindowFilesTest, OpenRecentListsReopensAndForgetsMissingFiles) {
  MainWindow window;
  show(window);
  const QString torusPath = QFileInfo(m_meshPath).absoluteFilePath();
  const QString spherePath = QFileInfo(m_spherePath).absoluteFilePath();
  ASSERT_TRUE(window.openMesh(m_meshPath));
  ASSERT_TRUE(window.openMesh(m_spherePath));
  EXPECT_EQ(window.recentFiles(), (QStringList{spherePath, torusPath}));
  auto* menu = window.findChild<QMenu*>(QStringLiteral("menuOpenRecent"));
  ASSERT_NE(menu, nullptr);
  ASSERT_TRUE(QMetaObject::invokeMethod(menu, "aboutToShow"));
  const QList<QAction*> items = menu->actions();
  ASSERT_EQ(items.size(), 2);
  EXPECT_EQ(items[0]->text(), QStringLiteral("sphere.off"));
  EXPECT_EQ(items[1]->text(), QStringLiteral("torus.off"));
  // Reopen the torus from the menu: read in the background, then first in the list.
  QSignalSpy loaded(&window, &MainWindow::meshLoaded);
  items[1]->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return loaded.count() == 1; }, 10000));
  EXPECT_EQ(window.viewport()->vertexCount(), static_cast<int>(m_mesh.V.rows()));
  EXPECT_EQ(window.recentFiles().value(0), torusPath);
  // A file gone since: dropped from the list when the menu opens, with a message naming it.
  ASSERT_TRUE(QFile::remove(m_spherePath));
  // every message the status bar shows from here (a late one, e.g. the reopened mesh's cleaning report under the
  // sanitiser's timing, may replace it at once)
  QSignalSpy messages(window.statusBar(), &QStatusBar::messageChanged);
  ASSERT_TRUE(QMetaObject::invokeMethod(menu, "aboutToShow"));
  EXPECT_EQ(window.recentFiles(), QStringList{torusPath});
  EXPECT_EQ(menu->actions().size(), 1);
  bool told = false;
  for (const QList<QVariant>& message : messages) told = told || message.value(0).toString().contains(spherePath);
  EXPECT_TRUE(told) << window.statusBar()->currentMessage().toStdString();
}

TEST_F(WindowFilesTest, CtrlSSavesTheHostedSessionUnderASuggestedName) {
  MainWindow window;
  show(window);
  ASSERT_TRUE(window.openMesh(m_spherePath));  // the dialogs' last folder: m_dir
  HostController* hosting = sc::testing::hostAndWait(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  auto* save = window.findChild<QAction*>(QStringLiteral("actionSaveSession"));
  ASSERT_NE(save, nullptr);
  EXPECT_EQ(save->shortcut(), QKeySequence(QKeySequence::Save));
  std::vector<FileRequest> requests;
  const QString target = m_dir.filePath(QStringLiteral("saved"));  // no suffix: .shapecast is added
  window.setFileChooser([&](const FileRequest& request, QString*) {
    requests.push_back(request);
    return target;
  });
  window.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window));
  QTest::keyClick(&window, Qt::Key_S, Qt::ControlModifier);
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].kind, FileRequest::Kind::Save);
  EXPECT_EQ(requests[0].suggestedName, QStringLiteral("torus.shapecast"));
  EXPECT_EQ(QFileInfo(requests[0].folder).absoluteFilePath(), QFileInfo(m_dir.path()).absoluteFilePath());
  EXPECT_TRUE(QFileInfo::exists(target + QStringLiteral(".shapecast")));
}

TEST_F(WindowFilesTest, CancelledLoadKeepsThePreviousMesh) {
  MainWindow window;
  show(window);
  ASSERT_TRUE(window.openMesh(m_spherePath));
  const auto large = sc::testing::torus(400, 200);  // 80,000 vertices
  const QString largePath = m_dir.filePath(QStringLiteral("large.off"));
  ASSERT_TRUE(sc::testing::writeOff(largePath, large.V, large.F));
  QSignalSpy loaded(&window, &MainWindow::meshLoaded);
  QSignalSpy cancelled(&window, &MainWindow::loadCancelled);
  window.loadMeshInBackground(largePath);
  EXPECT_TRUE(window.meshLoadRunning());
  QToolButton* cancel = cancelButton(window);
  ASSERT_NE(cancel, nullptr);
  EXPECT_TRUE(cancel->isVisible());
  EXPECT_TRUE(window.findChild<QProgressBar*>(QStringLiteral("sessionProgress"))->isVisible());
  cancel->click();
  EXPECT_EQ(cancelled.count(), 1);
  EXPECT_FALSE(window.meshLoadRunning());
  EXPECT_FALSE(cancel->isVisible());
  // The reader finishes its file in the background; its result is dropped.
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return window.findChild<QObject*>(QStringLiteral("meshLoading")) == nullptr; }, 30000));
  QTest::qWait(50);
  EXPECT_EQ(loaded.count(), 0);
  EXPECT_EQ(window.viewport()->vertexCount(), static_cast<int>(m_sphere.V.rows()));
  EXPECT_TRUE(window.windowTitle().startsWith(QStringLiteral("sphere.off")));
  // Not cancelled, the same file is shown.
  window.loadMeshInBackground(largePath);
  ASSERT_TRUE(QTest::qWaitFor([&] { return loaded.count() == 1; }, 30000));
  EXPECT_EQ(window.viewport()->vertexCount(), static_cast<int>(large.V.rows()));
}

TEST_F(WindowFilesTest, BrokenFileSaysWhyAndKeepsMeshAndSession) {
  MainWindow window;
  show(window);
  HostController* hosting = sc::testing::hostAndWait(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  const int hosted = window.viewport()->vertexCount();
  window.setSessionAsker([](const SessionQuestion&) { return SessionAnswer::End; });
  QSignalSpy failed(&window, &MainWindow::loadFailed);
  const QString broken = brokenFile();
  ASSERT_TRUE(window.openFileFromUser(broken));  // the read started; the session ends only once it worked
  ASSERT_TRUE(QTest::qWaitFor([&] { return failed.count() == 1; }, 10000));
  EXPECT_TRUE(failed.front().at(1).toString().contains(QStringLiteral("broken.off")))
      << failed.front().at(1).toString().toStdString();
  EXPECT_EQ(hosting->state(), State::Live);
  EXPECT_EQ(window.session(), hosting);
  EXPECT_EQ(window.viewport()->vertexCount(), hosted);
}

}  // namespace
}  // namespace sc::app
