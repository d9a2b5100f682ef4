// Issue 5 item 10 on a real loopback session inside one process (a hosting MainWindow and a joining MainWindow):
// the host takes the lock, paints a handle and anchors with the Handle and Anchors tools and drags with the Drag
// tool, all with simulated mouse strokes on its viewport; the client's displayed positions follow; each drag is a
// step of the session's edit history (issue 15); Edit → Undo on the host brings the client back to the previous
// shape and Redo forward again, with or without the lock; File → Export writes the client's
// displayed mesh, which model::loadMesh reads back with the client's vertex count; a screenshot is saved as PNG.

#include "app/gui/edit_actions.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/vertex_id_lists.h"
#include "app/gui/vertex_picking.h"
#include "app_test_support.h"
#include "model/mesh_loader.h"
#include "session/net/session_host.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QFile>
#include <QImage>
#include <QMouseEvent>
#include <QTest>

#include <cmath>
#include <filesystem>
#include <limits>
#include <span>
#include <variant>
#include <vector>

namespace sc::app {
namespace {

using sc::testing::copyOf;
using sc::testing::maxDifference;
using sc::testing::pixelStdDev;

using State = SessionController::State;

/// A left-button move with the button held (QTest::mouseMove carries no button state for widgets).
void moveTo(QWidget* widget, QPoint pos) {
  QMouseEvent event(QEvent::MouseMove, pos, widget->mapToGlobal(pos), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(widget, &event);
}

/// A left-button stroke from `from` to `to` in a few steps.
void stroke(QWidget* widget, QPoint from, QPoint to) {
  QTest::mousePress(widget, Qt::LeftButton, Qt::NoModifier, from);
  constexpr int kSteps = 6;
  for (int s = 1; s <= kSteps; ++s) {
    moveTo(widget, from + (to - from) * s / kSteps);
    QTest::qWait(5);
  }
  QTest::mouseRelease(widget, Qt::LeftButton, Qt::NoModifier, to);
}

class SessionUndoTest : public sc::testing::TorusSessionTest {
 protected:
  /// Screen position (widget pixels) of vertex `v` of interleaved `xyz` in `window`'s viewport (the viewport
  /// stores positions relative to the rest mesh's bounding-box centre), and whether it is in front of the camera.
  static QPoint screenOf(MainWindow& window, std::span<const float> xyz, const Eigen::RowVector3d& origin, int v) {
    std::vector<float> one{static_cast<float>(xyz[3 * v] - origin.x()), static_cast<float>(xyz[3 * v + 1] - origin.y()),
                           static_cast<float>(xyz[3 * v + 2] - origin.z())};
    const MeshViewport* view = window.viewport();
    const std::vector<ScreenPoint> p =
        projectToScreen(one, view->camera().view(), view->camera().projection(), view->size(), nullptr, 0.0f);
    return QPoint(static_cast<int>(p[0].x), static_cast<int>(p[0].y));
  }

  /// Among the vertices satisfying `pick`, the one nearest the host viewport's eye (visible for a convex-ish view).
  int nearestToEye(MainWindow& window, const Eigen::RowVector3d& origin, auto pick) const {
    const QVector3D eye = window.viewport()->camera().eye();
    const Eigen::RowVector3d e(eye.x(), eye.y(), eye.z());
    int best = -1;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < m_mesh.V.rows(); ++i) {
      if (!pick(m_mesh.V.row(i))) continue;
      const double d = (m_mesh.V.row(i) - origin - e).norm();
      if (d < bestDistance) {
        bestDistance = d;
        best = static_cast<int>(i);
      }
    }
    return best;
  }
};

TEST_F(SessionUndoTest, MouseDragOnTheHostMovesTheClientAndUndoBringsItBack) {
  MainWindow hostWindow;
  sc::testing::showSessionWindow(hostWindow, QSize(900, 700));
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&hostWindow));
  HostController* hosting = sc::testing::hostAndWait(hostWindow, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();

  MainWindow clientWindow;
  sc::testing::showSessionWindow(clientWindow, QSize(900, 700));
  ClientController* joined =
      sc::testing::joinAndWait(clientWindow, sc::testing::loopbackJoinSettings(hosting->tcpPort(), knownHostsFile()));
  ASSERT_EQ(joined->state(), State::Live) << joined->errorText().toStdString();
  const std::vector<float> rest = copyOf(joined->positions());
  ASSERT_EQ(rest.size(), static_cast<std::size_t>(3 * m_mesh.V.rows()));

  // Undo/redo live in the Edit menu and are off until there is something to undo.
  EditActions* history = hostWindow.editActions();
  ASSERT_NE(history, nullptr);
  const auto steps = [hosting] { return hosting->editLog().steps.size(); };
  auto* undoAction = hostWindow.findChild<QAction*>(QStringLiteral("actionUndo"));
  auto* redoAction = hostWindow.findChild<QAction*>(QStringLiteral("actionRedo"));
  ASSERT_NE(undoAction, nullptr);
  ASSERT_NE(redoAction, nullptr);
  EXPECT_EQ(undoAction->shortcut(), QKeySequence(QKeySequence::Undo));
  EXPECT_FALSE(undoAction->isEnabled());

  // The host takes the lock through the toolbar action.
  hostWindow.findChild<QAction*>(QStringLiteral("actionLock"))->trigger();
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return hosting->canDrag(); }, 5000));

  // Handle: a brush stroke on the outer rim at +x; anchors: a wide brush stroke on the −x side.
  MeshViewport* view = hostWindow.viewport();
  const Eigen::RowVector3d origin = 0.5 * (m_mesh.V.colwise().minCoeff() + m_mesh.V.colwise().maxCoeff());
  const int handleVertex = nearestToEye(hostWindow, origin, [](const auto& p) { return p(0) > 1.2; });
  const int anchorVertex = nearestToEye(hostWindow, origin, [](const auto& p) { return p(0) < -1.0; });
  ASSERT_GE(handleVertex, 0);
  ASSERT_GE(anchorVertex, 0);
  // Press a few pixels inside the vertex (towards the view's centre), safely on the surface.
  const auto inwards = [view](QPoint p) {
    const QPointF towards = QPointF(view->rect().center() - p);
    const double length = std::max(1.0, std::hypot(towards.x(), towards.y()));
    return p + (towards * (6.0 / length)).toPoint();
  };
  const QPoint handleAt = inwards(screenOf(hostWindow, rest, origin, handleVertex));
  const QPoint anchorAt = screenOf(hostWindow, rest, origin, anchorVertex);
  ASSERT_TRUE(view->rect().contains(handleAt)) << handleAt.x() << "," << handleAt.y();
  ASSERT_TRUE(view->rect().contains(anchorAt)) << anchorAt.x() << "," << anchorAt.y();

  hostWindow.findChild<QAction*>(QStringLiteral("actionToolHandle"))->trigger();
  ASSERT_EQ(view->tool(), ViewportTool::HandleBrush);
  view->setBrushRadius(15.0);
  stroke(view, handleAt, handleAt + QPoint(0, 4));
  ASSERT_FALSE(hosting->handle().empty());
  hostWindow.findChild<QAction*>(QStringLiteral("actionToolAnchors"))->trigger();
  view->setBrushRadius(40.0);
  stroke(view, anchorAt - QPoint(0, 20), anchorAt + QPoint(0, 20));
  ASSERT_FALSE(hosting->anchors().empty());
  EXPECT_GE(hosting->counters().constraintsAccepted, 2u);
  ASSERT_TRUE(hosting->sentConstraints().has_value());

  // The first mouse drag with the Drag tool: the client's displayed positions change and follow the host's.
  hostWindow.findChild<QAction*>(QStringLiteral("actionToolDrag"))->trigger();
  ASSERT_EQ(view->tool(), ViewportTool::Drag);
  ASSERT_TRUE(view->dragAllowed());
  stroke(view, handleAt, handleAt + QPoint(-50, -40));
  EXPECT_FALSE(hosting->dragging());
  EXPECT_EQ(steps(), 1u);
  EXPECT_EQ(hosting->editLog().steps[0].author, session::kHostPeer);
  EXPECT_GT(hosting->counters().dragsAccepted, 0u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), rest) > 0.05f; }, 10000))
      << maxDifference(joined->positions(), rest) << " host " << maxDifference(hosting->positions(), rest) << " handle "
      << hosting->handle().size() << " anchors " << hosting->anchors().size() << " at " << handleAt.x() << ","
      << handleAt.y() << " in " << view->width() << "x" << view->height();
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), hosting->positions()) < 1e-3f; }, 10000));
  const std::vector<float> afterFirst = copyOf(joined->positions());
  EXPECT_EQ(steps(), 1u);
  EXPECT_TRUE(undoAction->isEnabled());
  EXPECT_EQ(undoAction->text(), QStringLiteral("&Undo your drag"));
  EXPECT_FALSE(redoAction->isEnabled());

  // A second drag from where the handle is now.
  const QPoint movedHandle = inwards(screenOf(hostWindow, hosting->positions(), origin, handleVertex));
  ASSERT_TRUE(view->rect().contains(movedHandle))
      << movedHandle.x() << "," << movedHandle.y() << " in " << view->width() << "x" << view->height() << " from "
      << handleAt.x() << "," << handleAt.y();
  stroke(view, movedHandle, movedHandle + QPoint(-40, -30));
  ASSERT_EQ(steps(), 2u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), afterFirst) > 0.05f; }, 10000));
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), hosting->positions()) < 1e-3f; }, 10000));
  const std::vector<float> afterSecond = copyOf(joined->positions());

  // Undo (the Edit action) brings everyone back to the previous shape, twice to the rest shape; redo forward.
  undoAction->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), afterFirst) < 1e-3f; }, 10000))
      << maxDifference(joined->positions(), afterFirst);
  EXPECT_TRUE(redoAction->isEnabled());
  ASSERT_TRUE(history->undo());
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), rest) < 1e-3f; }, 10000))
      << maxDifference(joined->positions(), rest);
  EXPECT_FALSE(undoAction->isEnabled());
  redoAction->trigger();
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), afterFirst) < 1e-3f; }, 10000));
  ASSERT_TRUE(history->redo());
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), afterSecond) < 1e-3f; }, 10000));
  // Undo and redo change the shape, not the constraints: the handle and anchors shown stay.
  EXPECT_EQ(view->handles(), intIds<spectral::DisplayVertexTag>(hosting->handle()));

  // A drag after an undo starts from the shape as it is and ends the redo of the undone step (listed, undone).
  ASSERT_TRUE(history->undo());
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(hosting->positions(), afterFirst) < 1e-3f; }, 10000));
  const QPoint again = inwards(screenOf(hostWindow, hosting->positions(), origin, handleVertex));
  stroke(view, again, again + QPoint(0, 40));
  EXPECT_EQ(steps(), 3u);
  EXPECT_NE(hosting->editLog().steps[1].undoneBy, session::kNoPeer);
  EXPECT_FALSE(history->canRedo());

  // A client has nothing of its own to undo; the host may undo without the lock (undo is not a drag).
  ASSERT_TRUE(QTest::qWaitFor([&] { return joined->editLog().steps.size() == 3u; }, 5000));
  EXPECT_FALSE(clientWindow.editActions()->canUndo());
  hostWindow.findChild<QAction*>(QStringLiteral("actionLock"))->trigger();
  ASSERT_TRUE(QTest::qWaitFor([hosting] { return !hosting->canDrag(); }, 5000));
  EXPECT_TRUE(undoAction->isEnabled());
  const std::vector<float> beforeUndo = copyOf(hosting->positions());
  ASSERT_TRUE(history->undo());
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(hosting->positions(), afterFirst) < 1e-3f; }, 10000));
  ASSERT_TRUE(history->redo());
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(hosting->positions(), beforeUndo) < 1e-3f; }, 10000));

  // Export: the client's displayed mesh (its resolution, current shape) as OBJ and PLY, read back by loadMesh.
  ASSERT_TRUE(QTest::qWaitFor([&] { return maxDifference(joined->positions(), hosting->positions()) < 1e-3f; }, 10000));
  for (const char* name : {"client.obj", "client.ply"}) {
    const QString path = m_dir.filePath(QString::fromLatin1(name));
    QString error;
    ASSERT_TRUE(clientWindow.exportDeformedMesh(path, &error)) << error.toStdString();
    const model::MeshLoadResult loaded = model::loadMesh(std::filesystem::path(QFile::encodeName(path).toStdString()));
    ASSERT_TRUE(std::holds_alternative<model::LoadedMesh>(loaded)) << std::get<model::MeshError>(loaded).message;
    const auto& mesh = std::get<model::LoadedMesh>(loaded);
    EXPECT_EQ(mesh.V.rows(), clientWindow.viewport()->vertexCount()) << name;
    EXPECT_EQ(mesh.F.rows(), joined->displayFaces().rows()) << name;
    const std::vector<float> shown = joined->positions();
    double worst = 0.0;
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(mesh.V(i, c) - shown[3 * i + c]));
    EXPECT_LT(worst, 1e-5) << name << ": the deformed positions, not the rest shape";
  }
  QString error;
  EXPECT_FALSE(clientWindow.exportDeformedMesh(m_dir.filePath(QStringLiteral("client.stl")), &error));
  EXPECT_FALSE(error.isEmpty());

  // Screenshot: a PNG of the viewport that is not blank.
  const QString shot = m_dir.filePath(QStringLiteral("client.png"));
  ASSERT_TRUE(clientWindow.saveScreenshot(shot, &error)) << error.toStdString();
  const QImage image(shot);
  ASSERT_FALSE(image.isNull());
  EXPECT_GT(pixelStdDev(image), 5.0);
}

}  // namespace
}  // namespace sc::app
