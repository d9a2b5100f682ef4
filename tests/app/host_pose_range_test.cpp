// Issue 14, item 10, over the host's whole drag path: a window hosts a torus, drags its handle normally, then
// drags it by a finite but huge amount (1e300) and by NaN through the viewport's drag signals (as the mouse does).
// The huge poses are refused: the host keeps the previous, finite Z (so keyframes and datagrams keep carrying it)
// and the session can still be saved; a normal drag afterwards moves the mesh again.

#include "app/gui/first_start.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/session_controller.h"
#include "app/gui/vertex_id_lists.h"
#include "app/gui/vertex_picking.h"
#include "app_test_support.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QTest>

#include <cmath>
#include <limits>
#include <memory>

namespace sc::app {
namespace {

using State = SessionController::State;

class HostPoseRangeTest : public sc::testing::TorusSessionTest {};

/// One drag through the viewport's signals, as the mouse makes it.
void drag(MainWindow& window, const Eigen::Vector3d& translation) {
  MeshViewport* view = window.viewport();
  emit view->dragStarted();
  emit view->dragMoved(translation, Eigen::Matrix3d::Identity());
  emit view->dragFinished();
}

TEST_F(HostPoseRangeTest, HugeDragsAreRefusedAndThePreviousZKept) {
  auto window = std::make_unique<MainWindow>();
  sc::testing::showSessionWindow(*window, QSize(640, 480));
  SessionController* session = sc::testing::hostAndWait(*window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(session->state(), State::Live) << session->errorText().toStdString();
  ASSERT_TRUE(session->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([session] { return session->canDrag(); }, 5000));
  const Eigen::MatrixXd& V = session->displayRestPositions();
  const std::vector<int> handle = defaultHandle(V);
  const std::vector<int> anchors = defaultAnchors(V, handle, 40.0);
  window->viewport()->setSelection(handle, anchors);
  ASSERT_TRUE(
      session->setSelection(typedIds<spectral::DisplayVertexId>(handle), typedIds<spectral::DisplayVertexId>(anchors)));
  drag(*window, Eigen::Vector3d(0.0, 0.25, 0.0));
  ASSERT_TRUE(QTest::qWaitFor([session] { return session->coefficients().cwiseAbs().maxCoeff() > 1e-4; }, 5000));
  QTest::qWait(100);  // the drag's frame and its still frame
  const Eigen::MatrixXd before = session->coefficients();

  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector3d& huge :
       {Eigen::Vector3d(1e300, 0, 0), Eigen::Vector3d(0, -1e300, 1e300), Eigen::Vector3d(nan, 0, 0)}) {
    drag(*window, huge);
    QTest::qWait(100);
    const Eigen::MatrixXd Z = session->coefficients();
    EXPECT_TRUE(Z.allFinite()) << huge.transpose();
    EXPECT_EQ(Z, before) << huge.transpose();
  }
  QString error;
  EXPECT_TRUE(window->saveSession(m_dir.filePath(QStringLiteral("after.shapecast")), &error)) << error.toStdString();

  drag(*window, Eigen::Vector3d(0.0, -0.2, 0.1));  // a normal drag recovers
  EXPECT_TRUE(QTest::qWaitFor(
      [&] {
        return (session->coefficients() - before).cwiseAbs().maxCoeff() > 1e-4 && session->coefficients().allFinite();
      },
      5000));
}

}  // namespace
}  // namespace sc::app
