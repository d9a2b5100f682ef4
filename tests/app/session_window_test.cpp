// A real session on loopback inside one process: a hosting MainWindow and a joining MainWindow (real TCP and UDP
// sockets, the real basis, the real level transfer). The host takes the lock, sets a handle and anchors and drags
// through its SessionController; the client's displayed positions follow, the client cannot drag without the lock,
// switching its resolution keeps the deformation, and both windows' screenshots show something.

#include "app/gui/host_dialog.h"
#include "app/gui/join_dialog.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/session_docks.h"
#include "app_test_support.h"
#include "model/peer_table_model.h"
#include "model/statistics_model.h"
#include "session/net/session_host.h"
#include "session_windows.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/resolution_level.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QImage>
#include <QLabel>
#include <QLineEdit>
#include <QSignalSpy>
#include <QTest>
#include <QTimer>

#include <cmath>
#include <memory>
#include <vector>

namespace sc::app {
namespace {

using sc::testing::maxDifference;
using sc::testing::pixelStdDev;

using State = SessionController::State;

std::vector<float> interleaved(const Eigen::MatrixXd& V) {
  std::vector<float> out;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int c = 0; c < 3; ++c) out.push_back(float(V(i, c)));
  return out;
}

class SessionWindowTest : public sc::testing::TorusSessionTest {
 protected:
  /// Shows `window` and hosts the torus in it (m = 20, any port, password "secret", one person dragging at a time:
  /// the paper's lock, so that a second one waits); waits until it is live.
  HostController* host(MainWindow& window) {
    sc::testing::showSessionWindow(window, QSize(640, 480));
    HostSettings settings = sc::testing::loopbackHostSettings(m_meshPath, 20);
    settings.password = QStringLiteral("secret");
    settings.editors = 1;
    return sc::testing::hostAndWait(window, settings);
  }

  JoinSettings joinSettings(quint16 port, const QString& password) const {
    JoinSettings settings = sc::testing::loopbackJoinSettings(port, knownHostsFile());
    settings.password = password;
    return settings;
  }
};

TEST_F(SessionWindowTest, AJoinRefusedForItsPasswordAsksForItAgainInTheFilledInJoinForm) {
  MainWindow hostWindow;
  HostController* hosting = host(hostWindow);
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  const quint16 port = hosting->tcpPort();

  // No password, then a wrong one, then the right one: each refusal reopens the form, filled in as it was tried.
  MainWindow joiner;
  sc::testing::showSessionWindow(joiner, QSize(560, 420));
  joiner.setErrorDialogsEnabled(true);  // as in the app (showSessionWindow turns them off for the other tests)
  JoinSettings first = sc::testing::loopbackJoinSettings(port, knownHostsFile());
  first.name = QStringLiteral("zed");
  first.levelFraction = 0.5;
  const QStringList typed{QStringLiteral("wrong"), QStringLiteral("secret")};
  QStringList problems;
  QTimer answerer;  // plays the user at each form that opens
  QObject::connect(&answerer, &QTimer::timeout, [&] {
    auto* form = qobject_cast<JoinDialog*>(QApplication::activeModalWidget());
    if (form == nullptr || form->objectName() != QStringLiteral("passwordRetryDialog")) return;
    const JoinSettings shown = form->settings();
    EXPECT_EQ(shown.port, port);
    EXPECT_EQ(shown.name, QStringLiteral("zed"));
    EXPECT_EQ(shown.levelFraction, std::optional<double>(0.5));
    EXPECT_FALSE(shown.password.has_value()) << "the refused password is not shown again";
    problems << form->errorText();
    auto* password = form->findChild<QLineEdit*>(QStringLiteral("passwordEdit"));
    ASSERT_NE(password, nullptr);
    EXPECT_EQ(form->focusWidget(), password)
        << "the cursor goes to the password field";  // hasFocus() needs an active window
    password->setText(typed.value(static_cast<int>(problems.size()) - 1));
    form->accept();
  });
  answerer.start(50);
  joiner.joinSession(first);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return joiner.session() != nullptr && joiner.session()->state() == State::Live; }, 30000))
      << problems.join(QStringLiteral(" | ")).toStdString();
  answerer.stop();
  ASSERT_EQ(problems.size(), 2);
  EXPECT_TRUE(problems[0].contains(QStringLiteral("password"), Qt::CaseInsensitive)) << problems[0].toStdString();
  EXPECT_TRUE(problems[1].contains(QStringLiteral("password"), Qt::CaseInsensitive)) << problems[1].toStdString();
  EXPECT_TRUE(QTest::qWaitFor([hosting] { return hosting->peers().peers.size() == 2; }, 10000));
}

TEST_F(SessionWindowTest, HostAndClientDeformTogether) {
  MainWindow hostWindow;
  HostController* hosting = host(hostWindow);
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  EXPECT_EQ(hosting->role(), SessionController::Role::Host);
  const quint16 port = hosting->tcpPort();
  ASSERT_NE(port, 0);
  const auto n = static_cast<int>(m_mesh.V.rows());
  EXPECT_EQ(hostWindow.viewport()->vertexCount(), n);
  EXPECT_EQ(hosting->positions().size(), std::size_t(3 * n));

  // A wrong password fails with a readable message and never crashes.
  {
    MainWindow intruder;
    intruder.setErrorDialogsEnabled(false);
    QSignalSpy failures(&intruder, &MainWindow::sessionFailed);
    intruder.joinSession(joinSettings(port, QStringLiteral("wrong")));
    ASSERT_TRUE(QTest::qWaitFor([&failures] { return failures.count() > 0; }, 20000));
    EXPECT_EQ(intruder.session()->state(), State::Failed);
    EXPECT_FALSE(failures.first().first().toString().isEmpty());
  }

  MainWindow clientWindow;
  sc::testing::showSessionWindow(clientWindow, QSize(640, 480));
  ClientController* joined = sc::testing::joinAndWait(clientWindow, joinSettings(port, QStringLiteral("secret")));
  ASSERT_EQ(joined->state(), State::Live) << joined->errorText().toStdString();
  EXPECT_EQ(joined->role(), SessionController::Role::Client);
  EXPECT_EQ(clientWindow.viewport()->vertexCount(), n);  // the client shows the mesh
  const std::vector<float> rest = interleaved(joined->displayRestPositions());
  ASSERT_EQ(joined->positions().size(), rest.size());
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->peers().peers.size() == 2; }, 10000));

  // The host takes the lock; the client sees who holds it.
  ASSERT_TRUE(hosting->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->canDrag(); }, 5000));
  ASSERT_TRUE(QTest::qWaitFor([joined] { return joined->lockText().contains(QStringLiteral("alice")); }, 5000))
      << joined->lockText().toStdString();
  EXPECT_TRUE(hosting->lockText().contains(QStringLiteral("You hold")));
  EXPECT_EQ(hostWindow.findChild<QLabel*>(QStringLiteral("lockLabel"))->text(), hosting->lockText());

  // Handle: the outer rim at +x; anchors: everything at x < 0.
  spectral::DisplayVertexIds handle, anchors;
  for (int i = 0; i < n; ++i) {
    if (m_mesh.V(i, 0) > 1.2) handle.emplace_back(static_cast<std::uint32_t>(i));
    if (m_mesh.V(i, 0) < 0.0) anchors.emplace_back(static_cast<std::uint32_t>(i));
  }
  ASSERT_FALSE(handle.empty());
  ASSERT_TRUE(hosting->setSelection(handle, anchors));
  ASSERT_TRUE(hosting->beginDrag());
  ASSERT_TRUE(hosting->dragTo(Eigen::Vector3d(0.0, 0.0, 0.4), Eigen::Matrix3d::Identity()));
  hosting->endDrag();

  // The client's displayed positions change and converge to the host's.
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), rest) > 0.1f; }, 10000));
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), hosting->positions()) < 1e-3f; }, 10000));
  EXPECT_GT(maxDifference(hosting->positions(), rest), 0.1f);
  // The client's viewport reconstructs what it shows from the level and frame the controller pushed down
  // (MeshViewport::setDisplayLevel/showFrame): its positions are the session's, and the status bar reports that
  // reconstruction with the redraw.
  MeshViewport* clientViewport = clientWindow.viewport();
  EXPECT_TRUE(clientViewport->hasReconstructionBasis());
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return maxDifference(clientViewport->hostPositions(), joined->positions()) < 1e-5f; }, 5000));
  const auto* timing = clientWindow.findChild<QLabel*>(QStringLiteral("frameTimeLabel"));
  ASSERT_NE(timing, nullptr);
  ASSERT_TRUE(QTest::qWaitFor(
      [timing] { return timing->toolTip().startsWith(QStringLiteral("reconstruction + redraw: ")); }, 5000))
      << timing->toolTip().toStdString();
  EXPECT_TRUE(timing->text().startsWith(QStringLiteral("Frame: "))) << "plain words; the precise terms in the tooltip";
  EXPECT_GT(clientWindow.redrawMs(), 0.0);
  // The label's parts are the window's figures: the viewport's own reconstruction, then the rest of the redraw.
  EXPECT_TRUE(timing->toolTip().contains(QStringLiteral("(%1 + %2)")
                                             .arg(clientWindow.reconstructionMs(), 0, 'f', 2)
                                             .arg(clientWindow.redrawMs(), 0, 'f', 1)))
      << timing->toolTip().toStdString();
  // The join dialog's client extrapolates by default; after the drag stopped (the host's still frame) it shows a
  // received frame, not a prediction past it.
  ASSERT_TRUE(joined->reception().predicts);
  ASSERT_TRUE(QTest::qWaitFor([&] { return hosting->counters().stillFramesSent >= 1; }, 5000));
  ASSERT_TRUE(QTest::qWaitFor([&] { return joined->reception().received == hosting->currentFrame(); }, 5000));
  EXPECT_EQ(joined->reception().displayed, joined->reception().received);
  EXPECT_EQ(joined->reception().predictedFrames, 0);

  // Without the lock the client can neither constrain nor drag, and its viewport refuses drags.
  EXPECT_FALSE(joined->canDrag());
  EXPECT_FALSE(joined->setHandle(spectral::vertexIds<spectral::DisplayVertexId>(std::vector<std::uint32_t>{0, 1, 2})));
  EXPECT_FALSE(joined->beginDrag());
  EXPECT_FALSE(joined->dragTo(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(clientWindow.viewport()->dragAllowed());
  EXPECT_TRUE(hostWindow.viewport()->dragAllowed());
  // The client asks: it waits in the queue while the host holds the lock.
  ASSERT_TRUE(joined->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([joined] { return joined->lockText().contains(QStringLiteral("queue")); }, 5000))
      << joined->lockText().toStdString();

  // Switching the client's resolution keeps the deformation: positions of the new level are X̂' + K·Z.
  const std::vector<LevelChoice> levels = joined->levels();
  ASSERT_EQ(levels.size(), 4u);
  QSignalSpy meshChanges(joined, &SessionController::meshChanged);
  auto* combo = clientWindow.findChild<QComboBox*>(QStringLiteral("levelCombo"));
  ASSERT_NE(combo, nullptr);
  ASSERT_EQ(combo->count(), 4);
  EXPECT_TRUE(combo->isEnabled());
  ASSERT_TRUE(joined->setLevel(levels[2].target));  // ≈ 20 %
  ASSERT_TRUE(QTest::qWaitFor([&meshChanges] { return meshChanges.count() > 0; }, 20000));
  const spectral::ResolutionLevel* level = joined->level();
  ASSERT_NE(level, nullptr);
  const auto lowN = static_cast<int>(level->restV.rows());
  EXPECT_LT(lowN, n / 2);
  EXPECT_EQ(clientWindow.viewport()->vertexCount(), lowN);
  ASSERT_TRUE(QTest::qWaitFor([joined] { return joined->reception().hasFrame; }, 5000));
  const Eigen::MatrixXd Z = joined->coefficients();
  ASSERT_GT(Z.norm(), 0.0);  // still deformed
  std::vector<float> expected(3 * static_cast<std::size_t>(lowN));
  spectral::reconstructInterleaved(level->K, interleaved(level->restV), Z.cast<float>(), expected);
  EXPECT_LT(maxDifference(joined->positions(), expected), 1e-4f);
  EXPECT_GT(maxDifference(joined->positions(), interleaved(level->restV)), 0.05f);

  // Handles picked at the low level map to full-resolution ids (the client's turn needs the lock: release ours).
  ASSERT_TRUE(hosting->releaseLock());
  ASSERT_TRUE(QTest::qWaitFor([joined] { return joined->canDrag(); }, 5000)) << joined->lockText().toStdString();
  EXPECT_TRUE(joined->lockText().contains(QStringLiteral("You hold")));
  spectral::DisplayVertexIds lowHandle;
  for (int i = 0; i < lowN; ++i)
    if (level->restV(i, 1) > 1.0) lowHandle.emplace_back(static_cast<std::uint32_t>(i));
  ASSERT_FALSE(lowHandle.empty());
  EXPECT_TRUE(joined->setHandle(lowHandle));
  ASSERT_TRUE(joined->beginDrag());
  EXPECT_TRUE(joined->dragTo(Eigen::Vector3d(0.0, 0.3, 0.0), Eigen::Matrix3d::Identity()));
  joined->endDrag();
  // The constraints and the drag travel over TCP: wait for the host to accept both.
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->counters().constraintsAccepted >= 2; }, 5000));
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->counters().dragsAccepted >= 2; }, 5000));
  EXPECT_EQ(hosting->counters().constraintsRejected, 0u);

  // The host's docks: both peers in the table, the client's figures in its statistics model with non-zero
  // bandwidth (StatsReports arrive about once a second).
  SessionDocks* docks = hostWindow.docks();
  ASSERT_NE(docks, nullptr);
  EXPECT_EQ(docks->peerModel()->rowCount(), 2);
  // The host's sent rate covers the last second and a still shape sends nothing, so the client keeps dragging
  // until a sample shows both directions.
  const quint32 clientId = joined->selfId();
  ASSERT_TRUE(joined->beginDrag());
  int step = 0;
  ASSERT_TRUE(QTest::qWaitFor(
      [docks, clientId, joined, &step] {
        joined->dragTo(Eigen::Vector3d(0.0, 0.3 + 0.01 * (++step % 10), 0.0), Eigen::Matrix3d::Identity());
        const sc::model::StatisticsModel* statistics = docks->statisticsOf(clientId);
        return statistics != nullptr && statistics->latest() && statistics->latest()->kbpsIn > 0.0 &&
               statistics->latest()->kbpsOut > 0.0;
      },
      10000));
  joined->endDrag();
  const int clientRow = docks->peerModel()->rowOfPeer(clientId);
  ASSERT_GE(clientRow, 0);
  EXPECT_TRUE(docks->peerModel()->peerAt(clientRow).hasStats);

  // Screenshots are not blank.
  QTest::qWait(200);
  const QImage hostShot = hostWindow.grabWindow();
  const QImage clientShot = clientWindow.grabWindow();
  ASSERT_FALSE(hostShot.isNull());
  ASSERT_FALSE(clientShot.isNull());
  EXPECT_GT(pixelStdDev(hostShot), 5.0);
  EXPECT_GT(pixelStdDev(clientShot), 5.0);
  const QImage clientView = clientWindow.viewport()->grabFramebuffer();
  EXPECT_GT(pixelStdDev(clientView), 5.0);
  const QString out = qEnvironmentVariable("SHAPECAST_TEST_SCREENSHOTS");
  if (!out.isEmpty()) {
    hostShot.save(out + QStringLiteral("/session_host.png"));
    clientShot.save(out + QStringLiteral("/session_client.png"));
  }

  // The host leaves: the client reports that the host is gone.
  QSignalSpy clientFailures(&clientWindow, &MainWindow::sessionFailed);
  hostWindow.leaveSession();
  ASSERT_TRUE(QTest::qWaitFor([&clientFailures] { return clientFailures.count() > 0; }, 15000));
  EXPECT_TRUE(clientFailures.first().first().toString().contains(QStringLiteral("host")))
      << clientFailures.first().first().toString().toStdString();
}

TEST_F(SessionWindowTest, JoiningNobodyFailsReadably) {
  MainWindow window;
  window.setErrorDialogsEnabled(false);
  QSignalSpy failures(&window, &MainWindow::sessionFailed);
  JoinSettings settings = joinSettings(1, QString());  // nothing listens on port 1
  settings.password.reset();
  window.joinSession(settings);
  ASSERT_TRUE(QTest::qWaitFor([&failures] { return failures.count() > 0; }, 20000));
  EXPECT_TRUE(failures.first().first().toString().startsWith(QStringLiteral("Could not join")));
  EXPECT_EQ(window.session()->state(), State::Failed);
}

TEST_F(SessionWindowTest, HostingAMissingFileFailsAndCancelWorks) {
  HostController controller;
  QSignalSpy failures(&controller, &SessionController::failed);
  HostSettings settings;
  settings.meshPath = m_dir.filePath(QStringLiteral("missing.off"));
  settings.port = 0;
  settings.useBasisCache = false;
  ASSERT_TRUE(controller.host(settings));
  EXPECT_FALSE(controller.host(settings));  // one session per controller
  ASSERT_TRUE(QTest::qWaitFor([&failures] { return failures.count() > 0; }, 20000));
  EXPECT_EQ(controller.state(), State::Failed);

  HostController cancelled;
  QSignalSpy cancelFailures(&cancelled, &SessionController::failed);
  settings.meshPath = m_meshPath;
  ASSERT_TRUE(cancelled.host(settings));
  cancelled.cancel();
  ASSERT_TRUE(QTest::qWaitFor([&cancelled] { return cancelled.state() != State::Preparing; }, 20000));
  // Either the cancellation won the race or the (tiny) preparation finished first.
  EXPECT_TRUE(cancelled.state() == State::Failed || cancelled.state() == State::Live);
}

}  // namespace
}  // namespace sc::app
