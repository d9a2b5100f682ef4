// What a window shows once its session ended (issue 16): after Leave, "host lost" and a failed join the title,
// the host identity, the Peers and Statistics docks name no session; a failed join from inside a session keeps
// that session; a join that works replaces it. Real loopback sockets, windows in this process.

#include "app/gui/main_window.h"
#include "app/gui/session_docks.h"
#include "app/gui/statistics_dock.h"
#include "model/peer_table_model.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QHostAddress>
#include <QSignalSpy>
#include <QTcpServer>
#include <QTest>
#include <QToolButton>

namespace sc::app {
namespace {

using State = SessionController::State;

class SessionEndTest : public sc::testing::TorusSessionTest {
 protected:
  static QString identityText(const MainWindow& window) {
    return window.findChild<QToolButton*>(QStringLiteral("hostIdentityButton"))->text();
  }
  /// Nothing of a session on show but the shape: the title names `gone` no more, no identity, no peers or figures.
  static void expectNoSession(const MainWindow& window, const QString& gone) {
    EXPECT_FALSE(window.windowTitle().contains(gone)) << window.windowTitle().toStdString();
    EXPECT_FALSE(window.windowTitle().contains(QStringLiteral("hosting"))) << window.windowTitle().toStdString();
    EXPECT_TRUE(identityText(window).isEmpty()) << identityText(window).toStdString();
    EXPECT_EQ(window.docks()->peerModel()->rowCount(), 0);
    EXPECT_EQ(window.docks()->statisticsDock()->model(), nullptr);
  }
  /// A TCP port nobody listens on (connections to it are refused at once).
  static quint16 closedPort() {
    QTcpServer probe;
    EXPECT_TRUE(probe.listen(QHostAddress::LocalHost, 0));
    const quint16 port = probe.serverPort();
    probe.close();
    return port;
  }
};

TEST_F(SessionEndTest, LeaveAndHostLostResetTitleIdentityAndDocks) {
  MainWindow hostWindow;
  MainWindow clientWindow;
  const LiveSession live = hostAndJoin(hostWindow, clientWindow, {480, 360}, {480, 360});
  ASSERT_EQ(live.host->state(), State::Live);
  ASSERT_TRUE(live.client != nullptr && live.client->state() == State::Live);
  const QString port = QString::number(live.host->tcpPort());
  // Live: both show the session (the figures arrive with the first reports).
  ASSERT_TRUE(QTest::qWaitFor([&] { return clientWindow.docks()->peerModel()->rowCount() == 2; }, 10000));
  EXPECT_FALSE(identityText(hostWindow).isEmpty());
  EXPECT_FALSE(identityText(clientWindow).isEmpty());
  EXPECT_TRUE(hostWindow.windowTitle().contains(QStringLiteral("hosting")));
  EXPECT_TRUE(clientWindow.windowTitle().contains(port));
  QSignalSpy clientEnded(&clientWindow, &MainWindow::sessionEnded);
  // The host leaves: its own window, and the client's ("host lost": the host ended it).
  hostWindow.leaveSession();
  expectNoSession(hostWindow, port);
  EXPECT_TRUE(hostWindow.windowTitle().contains(QStringLiteral("torus")));  // the shape stays, named by its file
  ASSERT_TRUE(QTest::qWaitFor([&] { return clientEnded.count() == 1; }, 10000));
  EXPECT_EQ(live.client->state(), State::Failed);
  expectNoSession(clientWindow, port);
  EXPECT_GT(clientWindow.viewport()->vertexCount(), 0);  // the last shape stays displayed
}

TEST_F(SessionEndTest, FailedJoinWithoutASessionNamesNoSession) {
  MainWindow window;
  sc::testing::showSessionWindow(window, QSize(480, 360));
  const quint16 port = closedPort();
  ClientController* client =
      sc::testing::joinAndWait(window, sc::testing::loopbackJoinSettings(port, knownHostsFile()));
  ASSERT_NE(client, nullptr);
  ASSERT_EQ(client->state(), State::Failed);
  expectNoSession(window, QString::number(port));
}

TEST_F(SessionEndTest, FailedJoinInsideASessionKeepsIt) {
  MainWindow window;
  sc::testing::showSessionWindow(window, QSize(480, 360));
  HostController* hosting = sc::testing::hostAndWait(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  const QString title = window.windowTitle();
  const QString identity = identityText(window);
  QSignalSpy failed(&window, &MainWindow::sessionFailed);
  const quint16 port = closedPort();
  window.joinSession(sc::testing::loopbackJoinSettings(port, knownHostsFile()));
  EXPECT_NE(window.pendingJoin(), nullptr);
  EXPECT_EQ(window.session(), hosting);  // still hosting while the join connects
  ASSERT_TRUE(QTest::qWaitFor([&] { return failed.count() == 1; }, sc::testing::kSessionLiveTimeoutMs));
  EXPECT_TRUE(failed.front().front().toString().contains(QStringLiteral("still in the session")));
  EXPECT_EQ(window.pendingJoin(), nullptr);
  EXPECT_EQ(window.session(), hosting);
  EXPECT_EQ(hosting->state(), State::Live);
  EXPECT_EQ(window.windowTitle(), title);
  EXPECT_EQ(identityText(window), identity);
}

TEST_F(SessionEndTest, JoinInsideASessionReplacesItOnceLive) {
  MainWindow other;
  sc::testing::showSessionWindow(other, QSize(480, 360));
  HostController* theirs = sc::testing::hostAndWait(other, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(theirs->state(), State::Live) << theirs->errorText().toStdString();
  MainWindow window;
  sc::testing::showSessionWindow(window, QSize(480, 360));
  HostController* mine = sc::testing::hostAndWait(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(mine->state(), State::Live) << mine->errorText().toStdString();
  ClientController* client =
      sc::testing::joinAndWait(window, sc::testing::loopbackJoinSettings(theirs->tcpPort(), knownHostsFile()));
  ASSERT_NE(client, nullptr);
  ASSERT_EQ(client->state(), State::Live) << client->errorText().toStdString();
  EXPECT_EQ(window.session(), client);
  EXPECT_EQ(window.pendingJoin(), nullptr);
  EXPECT_TRUE(window.windowTitle().contains(QString::number(theirs->tcpPort())));
  EXPECT_GT(window.viewport()->vertexCount(), 0);
  // Its own session was left once the join was live: the other host sees just this client joined.
  ASSERT_TRUE(QTest::qWaitFor([&] { return theirs->peers().peers.size() == 2; }, 10000));
}

}  // namespace
}  // namespace sc::app
