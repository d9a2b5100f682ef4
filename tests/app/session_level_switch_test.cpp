// Issue 15: "Switching resolution drops the client's handle and anchors; the next drag says 'Paint a handle first',
// and repainting then resets the shape to rest." On a real loopback session (a hosting and a joining MainWindow in
// one process) the client paints a handle and anchors, drags, switches to a coarser level and drags again with the
// Drag tool without repainting: the press starts a drag, no new constraints are sent, and the shape keeps the first
// drag's displacement under the second one.

#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/vertex_id_lists.h"
#include "app/gui/vertex_picking.h"
#include "app_test_support.h"
#include "session/net/session_host.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QImage>
#include <QLineF>
#include <QMatrix4x4>
#include <QPointF>
#include <QSignalSpy>
#include <QTest>
#include <QVector3D>

#include <span>
#include <utility>
#include <vector>

namespace sc::app {
namespace {

using State = SessionController::State;

/// Mean displacement of `ids` between displayed positions `xyz` and rest `V` (the client's displayed level).
Eigen::Vector3d meanDisplacement(std::span<const float> xyz, const Eigen::MatrixXd& V,
                                 const spectral::DisplayVertexIds& ids) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const spectral::DisplayVertexId id : ids) {
    const auto i = static_cast<Eigen::Index>(id.index());
    sum +=
        Eigen::Vector3d(xyz[3 * id.index()], xyz[3 * id.index() + 1], xyz[3 * id.index() + 2]) - V.row(i).transpose();
  }
  return sum / static_cast<double>(ids.size());
}

/// A camera axis of `window`'s viewport in world coordinates (0: right, 1: up).
Eigen::Vector3d cameraAxis(MainWindow& window, int row) {
  const QMatrix4x4 view = window.viewport()->camera().view();
  return Eigen::Vector3d(view(row, 0), view(row, 1), view(row, 2)).normalized();
}

/// The displayed vertices within 0.3 of the one nearest to `window`'s eye (a patch the camera sees) and those
/// farther than 1.2 from it (anchors), of rest positions `rest`.
std::pair<std::vector<int>, std::vector<int>> facingPatch(MainWindow& window, const Eigen::MatrixXd& rest) {
  const Eigen::RowVector3d origin = 0.5 * (rest.colwise().minCoeff() + rest.colwise().maxCoeff());
  const QVector3D eye = window.viewport()->camera().eye();
  Eigen::Index nearest = 0;
  (rest.rowwise() - (origin + Eigen::RowVector3d(eye.x(), eye.y(), eye.z()))).rowwise().norm().minCoeff(&nearest);
  std::vector<int> handle, anchors;
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const double d = (rest.row(i) - rest.row(nearest)).norm();
    if (d < 0.3) handle.push_back(static_cast<int>(i));
    if (d > 1.2) anchors.push_back(static_cast<int>(i));
  }
  return {handle, anchors};
}

class SessionLevelSwitchTest : public sc::testing::TorusSessionTest {};

TEST_F(SessionLevelSwitchTest, HandleAndAnchorsSurviveAResolutionSwitchAndTheNextDragBuildsOnTheLast) {
  MainWindow hostWindow;
  MainWindow clientWindow;
  const LiveSession live = hostAndJoin(hostWindow, clientWindow);
  HostController* hosting = live.host;
  ClientController* joined = live.client;
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  ASSERT_NE(joined, nullptr);
  ASSERT_EQ(joined->state(), State::Live) << joined->errorText().toStdString();
  ASSERT_TRUE(joined->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([joined] { return joined->canDrag(); }, 5000)) << joined->lockText().toStdString();

  // The client paints (what a brush stroke ends in: the viewport shows the set, the window hands it to the session):
  // the handle on the outer rim at +x, anchors at x < 0.
  const Eigen::MatrixXd rest = joined->displayRestPositions();
  const auto [handle, anchors] = facingPatch(clientWindow, rest);
  ASSERT_FALSE(handle.empty());
  ASSERT_FALSE(anchors.empty());
  const Eigen::Vector3d up = cameraAxis(clientWindow, 1), right = cameraAxis(clientWindow, 0);
  MeshViewport* view = clientWindow.viewport();
  view->setSelection(handle, anchors);
  ASSERT_TRUE(
      joined->setSelection(typedIds<spectral::DisplayVertexId>(handle), typedIds<spectral::DisplayVertexId>(anchors)));
  ASSERT_TRUE(joined->beginDrag());
  ASSERT_TRUE(joined->dragTo(0.4 * up, Eigen::Matrix3d::Identity()));
  joined->endDrag();
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->counters().dragsAccepted >= 1; }, 5000));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return meanDisplacement(joined->positions(), joined->displayRestPositions(), joined->handle()).dot(up) > 0.2;
      },
      10000));
  const auto constraintsBefore = hosting->counters().constraintsAccepted;
  ASSERT_GE(constraintsBefore, 1u);

  // A coarser level: the handle and anchors are still there, in the session and in the viewport.
  const std::vector<LevelChoice> levels = joined->levels();
  ASSERT_GE(levels.size(), 3u);
  QSignalSpy meshChanges(joined, &SessionController::meshChanged);
  ASSERT_TRUE(joined->setLevel(levels[2].target));
  ASSERT_TRUE(QTest::qWaitFor([&meshChanges] { return meshChanges.count() > 0; }, 20000));
  ASSERT_LT(joined->displayRestPositions().rows(), rest.rows());
  EXPECT_FALSE(joined->handle().empty());
  EXPECT_FALSE(joined->anchors().empty());
  EXPECT_EQ(view->handles(), intIds<spectral::DisplayVertexTag>(joined->handle()));
  EXPECT_EQ(view->anchors(), intIds<spectral::DisplayVertexTag>(joined->anchors()));
  ASSERT_TRUE(QTest::qWaitFor([joined] { return joined->reception().hasFrame; }, 5000));
  EXPECT_GT(meanDisplacement(joined->positions(), joined->displayRestPositions(), joined->handle()).dot(up), 0.2)
      << "the new level shows the deformed shape";

  // The Drag tool, pressed on the (moved) handle of the new level, drags without repainting.
  QSignalSpy dragStarts(view, &MeshViewport::dragStarted);
  clientWindow.findChild<QAction*>(QStringLiteral("actionToolDrag"))->trigger();
  ASSERT_EQ(view->tool(), ViewportTool::Drag);
  QTest::qWait(FramePolicy::kIdleRestoreMs * 2);
  const std::vector<float> shown = view->hostPositions();
  const Eigen::RowVector3d origin =
      0.5 * (joined->displayRestPositions().colwise().minCoeff() + joined->displayRestPositions().colwise().maxCoeff());
  Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
  for (const int v : view->handles()) centroid += Eigen::RowVector3d(shown[3 * v], shown[3 * v + 1], shown[3 * v + 2]);
  centroid = centroid / static_cast<double>(view->handles().size()) - origin;
  const std::vector<float> xyz{static_cast<float>(centroid.x()), static_cast<float>(centroid.y()),
                               static_cast<float>(centroid.z())};
  const ScreenPoint p =
      projectToScreen(xyz, view->camera().view(), view->camera().projection(), view->size(), nullptr, 0.0f)[0];
  const QPoint at(static_cast<int>(p.x), static_cast<int>(p.y));
  ASSERT_TRUE(view->rect().contains(at)) << at.x() << "," << at.y();
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, at);
  EXPECT_EQ(dragStarts.count(), 1) << view->visibleHint().toStdString();
  EXPECT_TRUE(view->visibleHint().isEmpty()) << view->visibleHint().toStdString();
  EXPECT_TRUE(joined->dragging());
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, at);

  // A second drag through the session (as the viewport's would): accepted, on top of the first.
  ASSERT_TRUE(joined->beginDrag());
  ASSERT_TRUE(joined->dragTo(0.3 * right, Eigen::Matrix3d::Identity()));
  joined->endDrag();
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->counters().dragsAccepted >= 2; }, 5000));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return meanDisplacement(joined->positions(), joined->displayRestPositions(), joined->handle()).y() > 0.15;
      },
      10000));
  const Eigen::Vector3d moved = meanDisplacement(joined->positions(), joined->displayRestPositions(), joined->handle());
  EXPECT_GT(moved.dot(up), 0.2) << "the first drag's displacement stays (no reset to rest)";
  EXPECT_EQ(hosting->counters().constraintsAccepted, constraintsBefore) << "no new constraints were sent";
  EXPECT_EQ(hosting->counters().constraintsRejected, 0u);
}

/// Where the centroid of `ids` at the displayed positions of `window`'s viewport is on screen.
QPointF screenOfCentroid(MainWindow& window, const Eigen::MatrixXd& rest, const std::vector<int>& ids) {
  MeshViewport* view = window.viewport();
  const std::vector<float> shown = view->hostPositions();
  const Eigen::RowVector3d origin = 0.5 * (rest.colwise().minCoeff() + rest.colwise().maxCoeff());
  Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
  for (const int v : ids) centroid += Eigen::RowVector3d(shown[3 * v], shown[3 * v + 1], shown[3 * v + 2]);
  centroid = centroid / static_cast<double>(ids.size()) - origin;
  const std::vector<float> xyz{static_cast<float>(centroid.x()), static_cast<float>(centroid.y()),
                               static_cast<float>(centroid.z())};
  const ScreenPoint p =
      projectToScreen(xyz, view->camera().view(), view->camera().projection(), view->size(), nullptr, 0.0f)[0];
  return {p.x, p.y};
}

// Issue 15, "your own tint goes stale while someone else drags": the client's painted handle (it does not hold the
// lock) is tinted where the client shows it while the host drags that region.
TEST_F(SessionLevelSwitchTest, YourTintFollowsTheShapeWhileSomeoneElseDrags) {
  MainWindow hostWindow;
  MainWindow clientWindow;
  const LiveSession live = hostAndJoin(hostWindow, clientWindow);
  HostController* hosting = live.host;
  ClientController* joined = live.client;
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  ASSERT_NE(joined, nullptr);
  ASSERT_EQ(joined->state(), State::Live) << joined->errorText().toStdString();

  const Eigen::MatrixXd rest = joined->displayRestPositions();
  const auto [handle, anchors] = facingPatch(clientWindow, rest);
  ASSERT_FALSE(handle.empty());
  const Eigen::Vector3d up = cameraAxis(clientWindow, 1);
  MeshViewport* view = clientWindow.viewport();
  view->setSelection(handle, {});  // the client's own paint (kept; no lock, nothing sent)
  EXPECT_FALSE(joined->setHandle(typedIds<spectral::DisplayVertexId>(handle)));
  QTest::qWait(FramePolicy::kIdleRestoreMs * 2);
  const QPointF atRest = screenOfCentroid(clientWindow, rest, handle);
  EXPECT_LT(QLineF(sc::testing::handleTintCentroid(view->grabFramebuffer()), atRest).length(), 15.0);

  // The host drags the same region up.
  ASSERT_TRUE(hosting->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->canDrag(); }, 5000));
  ASSERT_TRUE(
      hosting->setSelection(typedIds<spectral::DisplayVertexId>(handle), typedIds<spectral::DisplayVertexId>(anchors)));
  ASSERT_TRUE(hosting->beginDrag());
  for (int step = 1; step <= 4; ++step) {
    ASSERT_TRUE(hosting->dragTo(0.12 * step * up, Eigen::Matrix3d::Identity()));
    QTest::qWait(30);
    const QImage moving = view->grabFramebuffer();
    const QPointF shown = screenOfCentroid(clientWindow, rest, handle);
    EXPECT_LT(QLineF(sc::testing::handleTintCentroid(moving), shown).length(), 15.0) << "moving frame " << step;
  }
  hosting->endDrag();
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return sc::testing::maxDifference(joined->positions(), hosting->positions()) < 1e-3f; }, 10000));
  QTest::qWait(FramePolicy::kIdleRestoreMs * 2);
  const QPointF moved = screenOfCentroid(clientWindow, rest, handle);
  ASSERT_GT(QLineF(moved, atRest).length(), 15.0) << "the handle moved on the client's screen";
  const QPointF tint = sc::testing::handleTintCentroid(view->grabFramebuffer());
  EXPECT_LT(QLineF(tint, moved).length(), 15.0) << "idle frame";
  EXPECT_LT(QLineF(tint, moved).length(), QLineF(tint, atRest).length()) << "not where the handle was";
}

}  // namespace
}  // namespace sc::app
