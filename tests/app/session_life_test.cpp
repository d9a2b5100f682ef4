// The life of a session seen from the windows (issue 15), over real loopback sockets: a hosting MainWindow and a
// joining one in this process, and a `shapecast-cli host` process stopped with SIGTERM. The questions before a
// session ends are answered by a SessionAsker (no modal box); what the other side reads is checked in its window.

#include "app/gui/session_life.h"
#include "app/gui/main_window.h"
#include "app_test_support.h"
#include "session/net/tls_identity.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QClipboard>
#include <QElapsedTimer>
#include <QGuiApplication>
#include <QLabel>
#include <QMenu>
#include <QProcess>
#include <QRegularExpression>
#include <QStatusBar>
#include <QTest>

#include <vector>

namespace sc::app {
namespace {

using State = SessionController::State;

class SessionLifeTest : public sc::testing::TorusSessionTest {
 protected:
  /// One person dragging at a time: these tests are about the lock's queue.
  HostController* host(MainWindow& window) {
    sc::testing::showSessionWindow(window, QSize(480, 360));
    HostSettings settings = sc::testing::loopbackHostSettings(m_meshPath, 20);
    settings.editors = 1;
    return sc::testing::hostAndWait(window, settings);
  }
  ClientController* join(MainWindow& window, quint16 port) {
    sc::testing::showSessionWindow(window, QSize(480, 360));
    return sc::testing::joinAndWait(window, sc::testing::loopbackJoinSettings(port, knownHostsFile()));
  }
  /// A host window and a client window in one live session (the host sees both peers).
  void startSession(MainWindow& hostWindow, MainWindow& clientWindow) {
    m_host = host(hostWindow);
    ASSERT_EQ(m_host->state(), State::Live) << m_host->errorText().toStdString();
    m_client = join(clientWindow, m_host->tcpPort());
    ASSERT_EQ(m_client->state(), State::Live) << m_client->errorText().toStdString();
    ASSERT_TRUE(QTest::qWaitFor([this] { return m_host->peers().peers.size() == 2; }, 10000));
  }
  static QString lockLine(const MainWindow& window) {
    return window.findChild<QLabel*>(QStringLiteral("lockLabel"))->text();
  }
  static QAction* action(const MainWindow& window, const char* name) {
    return window.findChild<QAction*>(QString::fromLatin1(name));
  }

  HostController* m_host = nullptr;
  ClientController* m_client = nullptr;
};

TEST_F(SessionLifeTest, TheHolderSeesWhoWaitsAndTheHostTakesTheLockBack) {
  MainWindow hostWindow, clientWindow;
  startSession(hostWindow, clientWindow);
  ASSERT_TRUE(m_host->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_host->canDrag(); }, 5000));
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_client->lockText().contains(QStringLiteral("alice")); }, 5000));
  EXPECT_EQ(action(clientWindow, "actionLock")->text(), QStringLiteral("Request lock"));

  // bob asks and waits: his button cancels, alice's line names him.
  action(clientWindow, "actionLock")->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return lockLine(hostWindow).contains(QStringLiteral("waiting")); }, 5000));
  EXPECT_EQ(lockLine(hostWindow), QStringLiteral("You hold the lock — bob is waiting"));
  EXPECT_EQ(action(hostWindow, "actionLock")->text(), QStringLiteral("Release lock"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return lockLine(clientWindow).contains(QStringLiteral("queue")); }, 5000));
  EXPECT_EQ(lockLine(clientWindow), QStringLiteral("Lock held by alice — you are 1st in the queue"));
  EXPECT_EQ(action(clientWindow, "actionLock")->text(), QStringLiteral("Cancel request"));

  // "Cancel request" cancels: alice's line no longer names anybody.
  action(clientWindow, "actionLock")->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return lockLine(hostWindow) == QStringLiteral("You hold the lock"); }, 5000))
      << lockLine(hostWindow).toStdString();
  ASSERT_TRUE(QTest::qWaitFor([this] { return !m_client->lockWanted(); }, 5000));
  EXPECT_EQ(action(clientWindow, "actionLock")->text(), QStringLiteral("Request lock"));

  // bob gets the lock; the host takes it back from the toolbar; bob reads why.
  ASSERT_TRUE(m_host->releaseLock());
  ASSERT_TRUE(m_client->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_client->canDrag(); }, 5000));
  // alice asks in turn: bob, the holder, reads that she waits.
  ASSERT_TRUE(m_host->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return lockLine(clientWindow).contains(QStringLiteral("waiting")); }, 5000));
  EXPECT_EQ(lockLine(clientWindow), QStringLiteral("You hold the lock — alice is waiting"));
  EXPECT_EQ(action(hostWindow, "actionLock")->text(), QStringLiteral("Cancel request"));
  QAction* takeBack = action(hostWindow, "actionForceRelease");
  ASSERT_NE(takeBack, nullptr);
  ASSERT_TRUE(QTest::qWaitFor([takeBack] { return takeBack->isEnabled(); }, 5000));
  EXPECT_FALSE(action(clientWindow, "actionForceRelease")->isVisible()) << "a client has no such power";
  takeBack->trigger();
  ASSERT_TRUE(QTest::qWaitFor([this] { return !m_client->canDrag(); }, 5000));
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_client->lockText().contains(QStringLiteral("alice")); }, 5000));
  EXPECT_EQ(m_client->lockText(), QStringLiteral("Lock held by alice — the host released your lock"))
      << "the queue's head, alice, has it now";
  EXPECT_EQ(lockLine(clientWindow), m_client->lockText());
  EXPECT_EQ(m_host->lockHolders(), std::vector<session::PeerId>{m_host->selfId()});
}

TEST_F(SessionLifeTest, AKickedClientReadsThatTheHostRemovedIt) {
  MainWindow hostWindow, clientWindow;
  startSession(hostWindow, clientWindow);
  ASSERT_TRUE(m_client->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_host->holdsLock(m_client->selfId()); }, 5000));
  EXPECT_EQ(hostWindow.peerContextMenu(m_host->selfId()), nullptr) << "nothing to do to oneself without the lock";
  QMenu* menu = hostWindow.peerContextMenu(m_client->selfId());
  ASSERT_NE(menu, nullptr);
  EXPECT_NE(menu->findChild<QAction*>(QStringLiteral("actionPeerForceRelease")), nullptr) << "bob holds the lock";
  QAction* remove = menu->findChild<QAction*>(QStringLiteral("actionKickPeer"));
  ASSERT_NE(remove, nullptr);
  EXPECT_EQ(clientWindow.peerContextMenu(m_host->selfId()), nullptr) << "a client removes nobody";
  remove->trigger();
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_client->state() == State::Failed; }, 10000));
  EXPECT_EQ(m_client->errorText(), QStringLiteral("The host removed you from the session."));
  EXPECT_EQ(clientWindow.statusBar()->currentMessage(), QStringLiteral("The host removed you from the session."));
  EXPECT_EQ(m_host->peers().peers.size(), 1u);
  EXPECT_TRUE(m_host->lockHolders().empty()) << "the kicked peer's lock is freed";
}

TEST_F(SessionLifeTest, QuittingTheHostAsksAndTheClientReadsThatTheHostEndedIt) {
  MainWindow hostWindow, clientWindow;
  startSession(hostWindow, clientWindow);
  std::vector<SessionQuestion> asked;
  SessionAnswer answer = SessionAnswer::Cancel;
  hostWindow.setSessionAsker([&](const SessionQuestion& question) {
    asked.push_back(question);
    return answer;
  });
  EXPECT_FALSE(hostWindow.close()) << "cancelled";
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0].text, QStringLiteral("1 person is in this session. End it for everyone?"));
  EXPECT_EQ(asked[0].endLabel, QStringLiteral("End session"));
  EXPECT_TRUE(hostWindow.isVisible());
  EXPECT_EQ(m_host->state(), State::Live);
  EXPECT_FALSE(hostWindow.leaveSessionAsking()) << "Session → Leave asks too";
  EXPECT_EQ(asked.size(), 2u);
  EXPECT_EQ(m_host->state(), State::Live);

  answer = SessionAnswer::End;
  hostWindow.close();
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_client->state() == State::Failed; }, 10000));
  EXPECT_EQ(m_client->errorText(), QStringLiteral("The host ended the session."))
      << "a Leave{HostEnded}, not \"host lost\"";
  EXPECT_EQ(clientWindow.statusBar()->currentMessage(), QStringLiteral("The host ended the session."));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !hostWindow.isVisible(); }, 5000)) << "closed once the Leaves are out";
}

TEST_F(SessionLifeTest, OpeningAnotherMeshWhileHostingAsksAndNeverReachesTheHostedModel) {
  MainWindow hostWindow, clientWindow;
  startSession(hostWindow, clientWindow);
  const auto sphere = sc::testing::icosphere(1);
  const QString other = m_dir.filePath(QStringLiteral("elephant.off"));
  ASSERT_TRUE(sc::testing::writeOff(other, sphere.V, sphere.F));
  std::vector<SessionQuestion> asked;
  SessionAnswer answer = SessionAnswer::Cancel;
  hostWindow.setSessionAsker([&](const SessionQuestion& question) {
    asked.push_back(question);
    return answer;
  });
  ASSERT_TRUE(m_host->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_host->canDrag(); }, 5000));
  const int hosted = hostWindow.viewport()->vertexCount();
  EXPECT_FALSE(hostWindow.openMeshAsking(other));
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0].text, QStringLiteral("You are hosting torus.off. Open elephant.off:"))
      << asked[0].text.toStdString();
  EXPECT_EQ(asked[0].rehostLabel, QStringLiteral("Host elephant.off instead"));
  EXPECT_EQ(m_host->state(), State::Live);
  EXPECT_EQ(hostWindow.viewport()->vertexCount(), hosted) << "cancelled: the hosted mesh stays";

  answer = SessionAnswer::End;
  ASSERT_TRUE(hostWindow.openMeshAsking(other));
  EXPECT_EQ(m_host->state(), State::Left);
  EXPECT_EQ(hostWindow.viewport()->vertexCount(), static_cast<int>(sphere.V.rows()));
  EXPECT_FALSE(m_host->canDrag()) << "the ended session's lock is gone: no handle, anchor or drag reaches it";
  EXPECT_FALSE(m_host->beginDrag());
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_client->state() == State::Failed; }, 10000));
  EXPECT_EQ(m_client->errorText(), QStringLiteral("The host ended the session."));

  // A joined client is asked too (leave first).
  MainWindow lone;
  HostController* second = host(lone);
  ASSERT_EQ(second->state(), State::Live);
  MainWindow joiner;
  ClientController* client = join(joiner, second->tcpPort());
  ASSERT_EQ(client->state(), State::Live);
  joiner.setSessionAsker([&](const SessionQuestion& question) {
    asked.push_back(question);
    return SessionAnswer::End;
  });
  ASSERT_TRUE(joiner.openMeshAsking(other));
  EXPECT_EQ(asked.back().endLabel, QStringLiteral("Leave the session and open"));
  EXPECT_TRUE(asked.back().rehostLabel.isEmpty());
  EXPECT_EQ(client->state(), State::Left);
  ASSERT_TRUE(QTest::qWaitFor([second] { return second->peers().peers.size() == 1; }, 10000));
}

TEST_F(SessionLifeTest, CopyInvitationPutsTheJoinCommandOnTheClipboard) {
  MainWindow hostWindow;
  EXPECT_TRUE(hostWindow.copyInvitation().isEmpty()) << "no session";
  QGuiApplication::clipboard()->setText(QStringLiteral("before"));
  HostController* hosting = host(hostWindow);
  ASSERT_EQ(hosting->state(), State::Live);
  QAction* copy = hostWindow.findChild<QAction*>(QStringLiteral("actionCopyInvitation"));
  ASSERT_NE(copy, nullptr);
  ASSERT_TRUE(copy->isEnabled());
  copy->trigger();
  const QString text = QGuiApplication::clipboard()->text();
  const QString hex = QString::fromLatin1(hosting->hostFingerprint().toHex());
  ASSERT_EQ(hex.size(), 64);
  const QRegularExpression command(
      QStringLiteral("Join with: shapecast --join (\\S+):%1 --fingerprint %2\\n").arg(hosting->tcpPort()).arg(hex));
  EXPECT_TRUE(command.match(text).hasMatch()) << text.toStdString();
  EXPECT_TRUE(text.contains(session::formatFingerprint(hosting->hostFingerprint()))) << text.toStdString();
  EXPECT_FALSE(text.contains(QStringLiteral("password"), Qt::CaseInsensitive));
  hostWindow.leaveSession();
  EXPECT_FALSE(copy->isEnabled());
}

TEST_F(SessionLifeTest, ACliHostStoppedWithSigtermEndsTheSessionForAWindow) {
  QProcess host;
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.insert(QStringLiteral("XDG_CACHE_HOME"), m_dir.filePath(QStringLiteral("cache")));
  environment.insert(QStringLiteral("XDG_CONFIG_HOME"), m_dir.filePath(QStringLiteral("config")));
  host.setProcessEnvironment(environment);
  host.start(QStringLiteral(SHAPECAST_CLI_EXE),
             {QStringLiteral("host"), m_meshPath, QStringLiteral("--port"), QStringLiteral("0"), QStringLiteral("--m"),
              QStringLiteral("20"), QStringLiteral("--no-cache"), QStringLiteral("--seconds"), QStringLiteral("120")});
  QString output;
  const QRegularExpression portLine(QStringLiteral("TCP port (\\d+)"));
  QElapsedTimer waited;
  waited.start();
  while (!portLine.match(output).hasMatch() && waited.elapsed() < 60000 && host.state() != QProcess::NotRunning) {
    host.waitForReadyRead(200);
    output += QString::fromUtf8(host.readAllStandardOutput());
  }
  const QRegularExpressionMatch port = portLine.match(output);
  ASSERT_TRUE(port.hasMatch()) << output.toStdString();

  MainWindow clientWindow;
  ClientController* client = join(clientWindow, static_cast<quint16>(port.captured(1).toUInt()));
  ASSERT_EQ(client->state(), State::Live) << client->errorText().toStdString();
  host.terminate();  // SIGTERM: the host sends Leave{HostEnded} before it exits
  ASSERT_TRUE(QTest::qWaitFor([client] { return client->state() == State::Failed; }, 10000));
  EXPECT_EQ(client->errorText(), QStringLiteral("The host ended the session.")) << "not \"host lost\"";
  EXPECT_EQ(clientWindow.statusBar()->currentMessage(), QStringLiteral("The host ended the session."));
  ASSERT_TRUE(host.waitForFinished(10000));
  EXPECT_EQ(host.exitCode(), 0);
}

TEST_F(SessionLifeTest, ACliClientRemovedByTheHostWindowSaysSoAndEnds) {
  MainWindow hostWindow;
  HostController* hosting = host(hostWindow);
  ASSERT_EQ(hosting->state(), State::Live);
  QProcess join;
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.insert(QStringLiteral("XDG_CONFIG_HOME"), m_dir.filePath(QStringLiteral("config")));
  join.setProcessEnvironment(environment);
  join.start(
      QStringLiteral(SHAPECAST_CLI_EXE),
      {QStringLiteral("join"), QStringLiteral("127.0.0.1:%1").arg(hosting->tcpPort()), QStringLiteral("--name"),
       QStringLiteral("carol"), QStringLiteral("--fingerprint"),
       QString::fromLatin1(hosting->hostFingerprint().toHex()), QStringLiteral("--seconds"), QStringLiteral("120")});
  // Joined and loaded (its first StatsReport comes after the level is installed).
  ASSERT_TRUE(QTest::qWaitFor(
      [hosting] { return hosting->peers().peers.size() == 2 && hosting->stats(hosting->peers().peers[1].peerId); },
      60000));
  const session::PeerId carol = hosting->peers().peers[1].peerId;
  EXPECT_EQ(hosting->peers().peers[1].name, QStringLiteral("carol"));
  QMenu* menu = hostWindow.peerContextMenu(carol);
  ASSERT_NE(menu, nullptr);
  QAction* remove = menu->findChild<QAction*>(QStringLiteral("actionKickPeer"));
  ASSERT_NE(remove, nullptr);
  remove->trigger();
  EXPECT_EQ(hosting->peers().peers.size(), 1u) << "gone from the list at once";
  ASSERT_TRUE(QTest::qWaitFor([&join] { return join.state() == QProcess::NotRunning; }, 20000))
      << "the client ends by itself";
  const QString output = QString::fromUtf8(join.readAllStandardOutput());
  EXPECT_TRUE(output.contains(QStringLiteral("session ended: The host removed you from the session.")))
      << output.toStdString() << join.readAllStandardError().toStdString();
  EXPECT_EQ(join.exitCode(), 0);
}

}  // namespace
}  // namespace sc::app
