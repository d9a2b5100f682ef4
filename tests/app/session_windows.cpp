#include "session_windows.h"

#include "app_test_support.h"

#include <QFile>
#include <QPointer>
#include <QTest>

namespace sc::testing {

using State = app::SessionController::State;

void showSessionWindow(app::MainWindow& window, QSize size) {
  window.setErrorDialogsEnabled(false);
  window.resize(size);
  window.show();
}

app::HostSettings loopbackHostSettings(const QString& meshPath, int m) {
  app::HostSettings settings;
  settings.meshPath = meshPath;
  settings.port = 0;
  settings.m = m;
  settings.name = QStringLiteral("alice");
  settings.useBasisCache = false;
  return settings;
}

app::JoinSettings loopbackJoinSettings(quint16 port, const QString& knownHostsFile) {
  app::JoinSettings settings;
  settings.host = QStringLiteral("127.0.0.1");
  settings.port = port;
  settings.name = QStringLiteral("bob");
  settings.knownHostsFile = knownHostsFile;
  return settings;
}

app::HostController* hostAndWait(app::MainWindow& window, const app::HostSettings& settings) {
  window.hostSession(settings);
  auto* session = qobject_cast<app::HostController*>(window.session());
  // The caller checks the state reached: a timeout leaves it Preparing.
  static_cast<void>(QTest::qWaitFor([session] { return session->state() != State::Preparing; }, kSessionLiveTimeoutMs));
  return session;
}

app::ClientController* joinAndWait(app::MainWindow& window, const app::JoinSettings& settings) {
  window.joinSession(settings);
  // In a session the join connects beside it (MainWindow::pendingJoin()) and is deleted if it fails.
  const QPointer<app::ClientController> session =
      qobject_cast<app::ClientController*>(window.pendingJoin() != nullptr ? window.pendingJoin() : window.session());
  // The caller checks the state reached: a timeout leaves it Connecting (or Transferring).
  // Joins are progressive (the host's smallest level first): Live counts once the requested level is shown.
  static_cast<void>(QTest::qWaitFor(
      [session] {
        return !session || (session->state() == State::Live && !session->levelPending()) ||
               session->state() == State::Failed;
      },
      kSessionLiveTimeoutMs));
  return session.data();
}

void TorusSessionTest::SetUp() {
  if (!openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (needs an X server)";
  ASSERT_TRUE(m_dir.isValid());
  m_mesh = torus(48, 24);
  m_meshPath = m_dir.filePath(QStringLiteral("torus.off"));
  ASSERT_TRUE(writeOff(m_meshPath, m_mesh.V, m_mesh.F));
}

QString TorusSessionTest::knownHostsFile() const { return m_dir.filePath(QStringLiteral("known_hosts.ini")); }

TorusSessionTest::LiveSession TorusSessionTest::hostAndJoin(app::MainWindow& hostWindow, app::MainWindow& clientWindow,
                                                            QSize hostSize, QSize clientSize) {
  LiveSession live;
  showSessionWindow(hostWindow, hostSize);
  live.host = hostAndWait(hostWindow, loopbackHostSettings(m_meshPath, 20));
  if (live.host->state() != app::SessionController::State::Live) return live;
  showSessionWindow(clientWindow, clientSize);
  static_cast<void>(QTest::qWaitForWindowExposed(&clientWindow));
  live.client = joinAndWait(clientWindow, loopbackJoinSettings(live.host->tcpPort(), knownHostsFile()));
  return live;
}

QString TorusSessionTest::writeLiftScript() const {
  QFile script(m_dir.filePath(QStringLiteral("drag.json")));
  EXPECT_TRUE(script.open(QIODevice::WriteOnly));
  script.write(R"({"handles":[{"sphere":{"vertex":0,"radius_pct":8}}],
                   "anchors":{"farther_than_pct":40,"from_vertex":0},
                   "frames":[{"t":0},{"t":1.0,"translate_pct":[0,15,0]},{"t":1.5,"translate_pct":[0,15,0]}]})");
  return script.fileName();
}

}  // namespace sc::testing
