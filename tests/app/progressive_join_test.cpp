// Issue 17 item 4, progressive join, in the desktop app: a hosting and a joining MainWindow in one process (real
// loopback sockets, the real basis and levels), the joining one over an emulated slow link. The host's shape is
// deformed before the join; the client window first shows the host's smallest level, deformed, with the status
// bar's progress bar naming the full model it is downloading ("Full detail N%"), then the full model with the same
// deformation, and the progress bar is hidden.

#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app_test_support.h"
#include "session/net/session_host.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QProgressBar>
#include <QTest>

#include <vector>

namespace sc::app {
namespace {

using State = SessionController::State;
using sc::testing::maxDifference;

std::vector<float> interleaved(const Eigen::MatrixXd& V) {
  std::vector<float> out;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(V(i, c)));
  }
  return out;
}

class ProgressiveJoinTest : public sc::testing::TorusSessionTest {};

TEST_F(ProgressiveJoinTest, TheSmallLevelShowsDeformedFirstThenTheFullOneWithAProgressBar) {
  MainWindow hostWindow;
  sc::testing::showSessionWindow(hostWindow, QSize(640, 480));
  HostController* hosting = sc::testing::hostAndWait(hostWindow, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  const auto n = static_cast<int>(m_mesh.V.rows());
  const std::vector<float> hostRest = interleaved(m_mesh.V);

  // The host deforms first: the outer rim at +x lifted, everything at x < 0 anchored.
  ASSERT_TRUE(hosting->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->canDrag(); }, 5000));
  spectral::DisplayVertexIds handle, anchors;
  for (int i = 0; i < n; ++i) {
    if (m_mesh.V(i, 0) > 1.2) handle.emplace_back(static_cast<std::uint32_t>(i));
    if (m_mesh.V(i, 0) < 0.0) anchors.emplace_back(static_cast<std::uint32_t>(i));
  }
  ASSERT_TRUE(hosting->setSelection(handle, anchors));
  ASSERT_TRUE(hosting->beginDrag());
  ASSERT_TRUE(hosting->dragTo(Eigen::Vector3d(0.0, 0.0, 0.4), Eigen::Matrix3d::Identity()));
  hosting->endDrag();
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(hosting->positions(), hostRest) > 0.1f; }, 10000));

  // The client joins over 0.25 Mbit/s: the full level (tens of kB) takes about a second, the smallest a fraction.
  MainWindow clientWindow;
  sc::testing::showSessionWindow(clientWindow, QSize(640, 480));
  JoinSettings settings = sc::testing::loopbackJoinSettings(hosting->tcpPort(), knownHostsFile());
  session::ImpairmentSettings link;
  link.rate.bitsPerSecond = 0.25e6;
  settings.impairment = link;
  clientWindow.joinSession(settings);
  auto* joined = qobject_cast<ClientController*>(clientWindow.session());
  ASSERT_NE(joined, nullptr);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return joined->state() != State::Connecting; }, sc::testing::kSessionLiveTimeoutMs));
  ASSERT_EQ(joined->state(), State::Live) << joined->errorText().toStdString();

  // First the smallest level, live and deformed, and the progress bar names what is coming.
  const auto* bar = clientWindow.findChild<QProgressBar*>(QStringLiteral("sessionProgress"));
  ASSERT_NE(bar, nullptr);
  const int smallCount = clientWindow.viewport()->vertexCount();
  EXPECT_GT(smallCount, 0);
  EXPECT_LT(smallCount, n / 10) << "the host's smallest level (5%) first";
  EXPECT_TRUE(joined->levelPending());
  const std::vector<float> smallRest = interleaved(joined->displayRestPositions());
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const std::vector<float> shown = joined->positions();
        return shown.size() == smallRest.size() && maxDifference(shown, smallRest) > 0.1f;
      },
      5000))
      << "the small level shows the deformed shape";
  EXPECT_EQ(clientWindow.viewport()->vertexCount(), smallCount) << "still the small level";
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return bar->isVisible() && bar->text().startsWith(QStringLiteral("Full detail")); }, 5000))
      << bar->text().toStdString();

  // Then the full model, with the same deformation, and the progress bar goes.
  ASSERT_TRUE(QTest::qWaitFor([&] { return clientWindow.viewport()->vertexCount() == n; }, 30000));
  EXPECT_FALSE(joined->levelPending());
  EXPECT_FALSE(bar->isVisible());
  EXPECT_GT(maxDifference(joined->positions(), hostRest), 0.1f) << "no return to the rest pose across the swap";
  EXPECT_LT(maxDifference(joined->positions(), hosting->positions()), 1e-3f) << "the host's shape on the full level";
}

}  // namespace
}  // namespace sc::app
