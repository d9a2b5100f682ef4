// The GUI viewer through NATS (issue 18 item 2): a real nats-server (LocalNatsServer, stopped by its PID), a child
// `shapecast-cli host --nats` and a MainWindow that watches the session (MainWindow::watchSession, ViewerController):
// the window shows the relayed level (the torus' vertex count, fetched from the level stream), stays read-only (no
// lock, no drag; "Watching test through NATS"), shows the deformed shape after a `shapecast-cli drive` drag, counts
// the frames and the distortion (0: it got every frame) in its statistics, and switches to a coarser level from the
// stream.
#include "app/gui/main_window.h"
#include "app/gui/viewer_controller.h"
#include "host_process.h"
#include "session/engine/frame_assembler.h"
#include "session/engine/relay_display.h"
#include "session/net/local_nats_server.h"
#include "session/net/relay_viewer.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QFile>
#include <QProcess>
#include <QTest>

#include <algorithm>
#include <cmath>

namespace sc::app {
namespace {

using State = SessionController::State;

class RelayWatchWindow : public testing::TorusSessionTest {
 protected:
  void SetUp() override {
    if (!session::natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
    TorusSessionTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    QString error;
    ASSERT_TRUE(m_server.start(&error)) << error.toStdString();
    QFile password(m_dir.filePath(QStringLiteral("host.pw")));
    ASSERT_TRUE(password.open(QIODevice::WriteOnly));
    password.write(m_server.config().hostPassword.toUtf8() + '\n');
  }

  session::LocalNatsServer m_server;
};

/// Largest |a − b| over two position buffers of the same size.
double largestDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double out = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) out = std::max(out, std::abs(double(a[i]) - b[i]));
  return out;
}

TEST_F(RelayWatchWindow, ShowsTheRelayedLevelReadOnlyAndTheDeformedShapeAfterADrag) {
  testing::HostProcess host(
      m_meshPath, {QStringLiteral("--nats"), m_server.url(), QStringLiteral("--session"), m_server.config().sessionId,
                   QStringLiteral("--nats-user"), m_server.config().hostUser, QStringLiteral("--nats-password-file"),
                   m_dir.filePath(QStringLiteral("host.pw"))});
  ASSERT_NE(host.port(), 0) << "the host did not print its port";

  MainWindow window;
  testing::showSessionWindow(window, {800, 600});
  WatchSettings settings;
  settings.url = m_server.url();
  settings.sessionId = m_server.config().sessionId;
  settings.user = m_server.config().viewerUser;
  settings.password = m_server.config().viewerPassword;
  // The relay starts right after the host's port line: retry while its session is not on the broker yet.
  for (int attempt = 0; attempt < 20; ++attempt) {
    window.watchSession(settings);
    if (window.session()->state() != State::Failed) break;
    QTest::qWait(250);
  }
  auto* viewer = qobject_cast<ViewerController*>(window.session());
  ASSERT_NE(viewer, nullptr);
  ASSERT_TRUE(QTest::qWaitFor([viewer] { return viewer->state() != State::Connecting; }, 30000));
  ASSERT_EQ(viewer->state(), State::Live) << viewer->errorText().toStdString();

  // The full level from the stream: the torus' vertices and faces.
  ASSERT_TRUE(viewer->displayLevel());
  EXPECT_EQ(viewer->displayLevel()->vertexCount(), static_cast<std::uint32_t>(m_mesh.V.rows()));
  EXPECT_EQ(viewer->displayFaces().rows(), m_mesh.F.rows());
  EXPECT_EQ(viewer->hostFingerprint().size(), 32);
  // Read-only: no lock to ask for, no drag, and the status says what this window is.
  ASSERT_TRUE(viewer->readOnlyText());
  EXPECT_EQ(*viewer->readOnlyText(), QStringLiteral("Watching test through NATS"));
  EXPECT_FALSE(viewer->requestLock());
  EXPECT_FALSE(viewer->canDrag());
  QAction* lock = window.findChild<QAction*>(QStringLiteral("actionLock"));
  ASSERT_NE(lock, nullptr);
  EXPECT_FALSE(lock->isEnabled());
  const std::vector<float> before = viewer->positions();

  const QString script = writeLiftScript();
  QProcess drive;
  drive.start(QStringLiteral(SHAPECAST_CLI),
              {QStringLiteral("drive"), host.address(), QStringLiteral("--script"), script});
  ASSERT_TRUE(drive.waitForStarted());
  ASSERT_TRUE(QTest::qWaitFor([&drive] { return drive.state() == QProcess::NotRunning; }, 60000));
  EXPECT_EQ(drive.exitCode(), 0) << drive.readAllStandardError().toStdString();
  // The deformed shape is shown: the handle moved by 15% of the diagonal (> 0.05 on this torus of diagonal ≈ 2.9).
  ASSERT_TRUE(QTest::qWaitFor([&] { return largestDifference(viewer->positions(), before) > 0.05; }, 10000))
      << largestDifference(viewer->positions(), before);
  const std::optional<session::StatsReport> stats = viewer->stats(viewer->selfId());
  ASSERT_TRUE(stats);
  EXPECT_GT(stats->framesApplied, 10u);
  EXPECT_EQ(stats->lost, 0u);
  EXPECT_EQ(stats->dropped, 0u);
  // Distortion against the host's keyframes read back (once a second): this viewer got every frame, exact, so what
  // it showed for each reference was that very shape. The Statistics dock plots hdLastPct.
  ASSERT_TRUE(QTest::qWaitFor([viewer] { return viewer->viewer()->display().distortion().count >= 1; }, 10000));
  EXPECT_EQ(viewer->stats(viewer->selfId())->hdMaxPct, 0.0);
  EXPECT_EQ(viewer->viewer()->display().concealment(), session::Concealment::HoldLast);  // no app setting: hold-last

  // Another level from the stream: the coarsest listed.
  ASSERT_TRUE(QTest::qWaitFor([viewer] { return viewer->levels().size() > 1; }, 30000));
  std::uint32_t coarsest = viewer->levels().front().target;
  for (const LevelChoice& level : viewer->levels()) {
    if (level.target != 0) coarsest = std::min(coarsest == 0 ? level.target : coarsest, level.target);
  }
  ASSERT_GT(coarsest, 0u);
  ASSERT_TRUE(viewer->setLevel(coarsest));
  ASSERT_TRUE(QTest::qWaitFor([viewer, coarsest] { return viewer->displayLevel()->vertexCount() == coarsest; }, 30000));
  EXPECT_EQ(viewer->state(), State::Live);
  EXPECT_EQ(viewer->positions().size(), 3u * coarsest);
  host.stop();
}

}  // namespace
}  // namespace sc::app
