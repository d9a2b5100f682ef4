// The session dialogs without a session: the Host and Join forms' validation messages, the recent-sessions list
// (which never stores a password), and a join cancelled while it connects (no error box).

#include "app/gui/host_dialog.h"
#include "app/gui/join_dialog.h"
#include "app/gui/main_window.h"
#include "app/gui/recent_sessions.h"
#include "app_test_support.h"
#include "session_windows.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QFile>
#include <QMessageBox>
#include <QSettings>
#include <QTcpServer>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

namespace sc::app {
namespace {

TEST(SessionDialogs, ValidationMessages) {
  HostSettings host;
  EXPECT_FALSE(validateHostSettings(host).isEmpty());  // no mesh
  QTemporaryDir dir;
  host.meshPath = dir.filePath(QStringLiteral("nothing.off"));
  EXPECT_TRUE(validateHostSettings(host).contains(QStringLiteral("does not exist")));
  const auto mesh = sc::testing::torus(8, 6);
  host.meshPath = dir.filePath(QStringLiteral("t.off"));
  ASSERT_TRUE(sc::testing::writeOff(host.meshPath, mesh.V, mesh.F));
  EXPECT_TRUE(validateHostSettings(host).isEmpty());
  host.m = 0;
  EXPECT_FALSE(validateHostSettings(host).isEmpty());
  host.m = 50;
  host.name = QString(100, QLatin1Char('x'));
  EXPECT_TRUE(validateHostSettings(host).contains(QStringLiteral("too long")));

  JoinSettings join;
  join.name = QStringLiteral("bob");
  EXPECT_TRUE(validateJoinSettings(join).isEmpty());
  join.host = QStringLiteral("not a host");
  EXPECT_FALSE(validateJoinSettings(join).isEmpty());
  join.host = QStringLiteral("example.org");
  join.port = 0;
  EXPECT_FALSE(validateJoinSettings(join).isEmpty());
  join.port = 47100;
  join.name.clear();
  EXPECT_FALSE(validateJoinSettings(join).isEmpty());
}

TEST(SessionDialogs, RecentSessionsNeverStorePasswords) {
  QTemporaryDir dir;
  const QString file = dir.filePath(QStringLiteral("recent.ini"));
  {
    QSettings settings(file, QSettings::IniFormat);
    RecentSessions recent = RecentSessions::load(settings);
    HostSettings host;
    host.meshPath = QStringLiteral("/meshes/a.off");
    host.password = QStringLiteral("hunter2");
    host.port = 5000;
    recent.rememberHost(host);
    JoinSettings join;
    join.host = QStringLiteral("10.0.0.2");
    join.port = 6000;
    join.name = QStringLiteral("bob");
    join.password = QStringLiteral("hunter2");
    recent.rememberJoin(join);
    recent.rememberJoin(join);  // no duplicates
    recent.save(settings);
  }
  QSettings settings(file, QSettings::IniFormat);
  const RecentSessions recent = RecentSessions::load(settings);
  EXPECT_EQ(recent.meshPaths, QStringList{QStringLiteral("/meshes/a.off")});
  EXPECT_EQ(recent.hosts, QStringList{QStringLiteral("10.0.0.2")});
  EXPECT_EQ(recent.hostPort, 5000);
  EXPECT_EQ(recent.joinPort, 6000);
  QFile raw(file);
  ASSERT_TRUE(raw.open(QIODevice::ReadOnly));
  EXPECT_FALSE(raw.readAll().contains("hunter2"));
}

TEST(SessionCancel, CancellingAJoinShowsNoErrorDialog) {
  // Cancel showed a modal "Cancelled." warning, as if something had gone wrong.
  if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (needs an X server)";
  QTcpServer silent;  // accepts, never answers TLS: the join stays Connecting
  ASSERT_TRUE(silent.listen(QHostAddress::LocalHost));
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  MainWindow window;  // error dialogs on
  int boxes = 0;
  QTimer watcher;
  QObject::connect(&watcher, &QTimer::timeout, [&boxes] {
    if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
      ++boxes;
      box->reject();
    }
  });
  watcher.start(20);
  window.joinSession(sc::testing::loopbackJoinSettings(silent.serverPort(), dir.filePath(QStringLiteral("known.ini"))));
  ASSERT_TRUE(QTest::qWaitFor([&window] { return window.session() != nullptr; }, 5000));
  ASSERT_EQ(window.session()->state(), SessionController::State::Connecting);
  window.session()->cancel();
  QTest::qWait(300);
  EXPECT_EQ(window.session()->state(), SessionController::State::Failed);
  EXPECT_TRUE(window.session()->cancelledByUser());
  EXPECT_EQ(boxes, 0);
}

}  // namespace
}  // namespace sc::app
