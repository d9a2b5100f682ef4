// Tests for src/app/gui/viewport/viewport_surface.cpp: MeshViewport's window surface (issue 16 item 5). Events that
// reach the embedded window (a real pointer over the 3D view) drive the viewport's own input, the surface paints
// on its own, and grabFramebuffer() returns the picture with the overlay (needs an X server with GL; skipped
// otherwise).

#include "app/gui/viewport/viewport_surface.h"
#include "app/gui/mesh_viewport.h"

#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QColor>
#include <QImage>
#include <QMouseEvent>
#include <QTest>

namespace {

using sc::app::MeshViewport;
using sc::app::ViewportTool;

class ViewportSurfaceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) {
      GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
    }
    const auto sphere = sc::testing::icosphere(3);
    m_viewport.resize(320, 240);
    m_viewport.setMesh(sphere.V, sphere.F);
    m_viewport.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&m_viewport));
  }

  // A mouse event as the window system delivers it: to the surface window, in its coordinates.
  void sendToSurface(QEvent::Type type, QPoint pos, Qt::MouseButton button, Qt::MouseButtons buttons) {
    QWindow* window = m_viewport.surface();
    QMouseEvent event(type, pos, window->mapToGlobal(pos), button, buttons, Qt::NoModifier);
    QCoreApplication::sendEvent(window, &event);
  }

  MeshViewport m_viewport;
};

TEST_F(ViewportSurfaceTest, TheWindowFillsTheWidgetAndPaintsOnItsOwn) {
  ASSERT_NE(m_viewport.surface(), nullptr);
  EXPECT_TRUE(QTest::qWaitFor([this] { return m_viewport.paintCount() > 0; }, 5000)) << "the surface painted";
  EXPECT_EQ(m_viewport.surface()->size(), m_viewport.size());
  const int painted = m_viewport.paintCount();
  m_viewport.repaint();  // synchronous on an exposed window
  EXPECT_EQ(m_viewport.paintCount(), painted + 1);
}

TEST_F(ViewportSurfaceTest, MouseEventsOnTheWindowDriveTheViewportsInput) {
  m_viewport.setTool(ViewportTool::Orbit);
  int moved = 0;
  QObject::connect(&m_viewport, &MeshViewport::cameraMovedByUser, [&moved] { ++moved; });
  const QVector3D eye = m_viewport.camera().eye();
  sendToSurface(QEvent::MouseButtonPress, {100, 100}, Qt::LeftButton, Qt::LeftButton);
  sendToSurface(QEvent::MouseMove, {160, 120}, Qt::NoButton, Qt::LeftButton);
  sendToSurface(QEvent::MouseButtonRelease, {160, 120}, Qt::LeftButton, Qt::NoButton);
  EXPECT_GT(moved, 0) << "the orbit drag reached ViewportInput";
  EXPECT_GT((m_viewport.camera().eye() - eye).length(), 1e-3f);
}

TEST_F(ViewportSurfaceTest, GrabShowsTheMeshAndTheBrushOutline) {
  m_viewport.setTool(ViewportTool::HandleBrush);
  const QImage plain = m_viewport.grabFramebuffer();
  ASSERT_FALSE(plain.isNull());
  EXPECT_EQ(plain.size(), m_viewport.size() * m_viewport.devicePixelRatio());
  const QColor centre = plain.pixelColor(plain.width() / 2, plain.height() / 2);
  const QColor corner = plain.pixelColor(2, 2);
  EXPECT_NE(centre, corner) << "the sphere over the background";
  // Hovering over the window draws the brush outline (QPainter over the GL passes) into the grab too.
  sendToSurface(QEvent::MouseMove, {60, 60}, Qt::NoButton, Qt::NoButton);
  const QImage outlined = m_viewport.grabFramebuffer();
  EXPECT_GT(sc::testing::countDifferentPixels(plain, outlined), 50) << "the brush outline";
}

}  // namespace
