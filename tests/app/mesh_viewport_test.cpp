// Tests for src/app/gui/mesh_viewport.cpp: what the widget actually renders (needs an X server with GL; skipped
// otherwise).

#include "app/gui/mesh_viewport.h"

#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QColor>
#include <QMouseEvent>
#include <QTest>
#include <QWheelEvent>

#include <algorithm>
#include <cstdlib>
#include <utility>

namespace {

class MeshViewportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) {
      GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
    }
    m_viewport.resize(320, 240);
    m_viewport.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&m_viewport));
    m_background = m_viewport.grabFramebuffer();
    ASSERT_FALSE(m_background.isNull());
  }

  QImage grab() { return m_viewport.grabFramebuffer(); }

  void sendMouse(QEvent::Type type, QPoint pos, Qt::MouseButton button, Qt::MouseButtons buttons) {
    QMouseEvent event(type, pos, m_viewport.mapToGlobal(pos), button, buttons, Qt::NoModifier);
    QApplication::sendEvent(&m_viewport, &event);
  }

  sc::app::MeshViewport m_viewport;
  QImage m_background;
};

// Pixels where some colour channel differs by more than threshold.
int countPixelsDifferingBy(const QImage& a, const QImage& b, int threshold) {
  int count = 0;
  for (int y = 0; y < a.height(); ++y) {
    for (int x = 0; x < a.width(); ++x) {
      const QColor p(a.pixel(x, y));
      const QColor q(b.pixel(x, y));
      const int difference =
          std::max({std::abs(p.red() - q.red()), std::abs(p.green() - q.green()), std::abs(p.blue() - q.blue())});
      count += difference > threshold ? 1 : 0;
    }
  }
  return count;
}

}  // namespace

TEST_F(MeshViewportTest, BackgroundIsAVerticalGradient) {
  const int w = m_background.width();
  const int h = m_background.height();
  EXPECT_EQ(m_background.pixel(0, 0), m_background.pixel(w - 1, 0)) << "constant along a row";
  EXPECT_GT(QColor(m_background.pixel(0, 0)).lightness(), QColor(m_background.pixel(0, h - 1)).lightness())
      << "lighter at the top";
}

TEST_F(MeshViewportTest, RendersIcosphereFramedInTheCentre) {
  const auto sphere = sc::testing::icosphere(3, 5.0, Eigen::Vector3d(100, 200, -50));
  m_viewport.setMesh(sphere.V, sphere.F);
  EXPECT_EQ(m_viewport.vertexCount(), 642);
  EXPECT_EQ(m_viewport.triangleCount(), 1280);
  const QImage image = grab();
  ASSERT_EQ(image.size(), m_background.size());
  const int w = image.width();
  const int h = image.height();
  EXPECT_NE(image.pixel(w / 2, h / 2), m_background.pixel(w / 2, h / 2)) << "the sphere covers the centre";
  for (const QPoint corner : {QPoint(0, 0), QPoint(w - 1, 0), QPoint(0, h - 1), QPoint(w - 1, h - 1)}) {
    EXPECT_EQ(image.pixel(corner), m_background.pixel(corner)) << "corners show the background";
  }
  // Auto-framing: the sphere is centred and spans a good part of the height without touching the border.
  const QRect bounds = sc::testing::differingBounds(image, m_background);
  EXPECT_NEAR(bounds.center().x(), w / 2, w / 20);
  EXPECT_NEAR(bounds.center().y(), h / 2, h / 20);
  EXPECT_GT(bounds.height(), h / 2);
  EXPECT_TRUE(QRect(1, 1, w - 2, h - 2).contains(bounds));
}

TEST_F(MeshViewportTest, ShadingVariesAcrossTheSurface) {
  const auto sphere = sc::testing::icosphere(3);
  m_viewport.setMesh(sphere.V, sphere.F);
  const QImage image = grab();
  const QRect bounds = sc::testing::differingBounds(image, m_background);
  int darkest = 255;
  int lightest = 0;
  for (int y = bounds.top() + bounds.height() / 4; y < bounds.bottom() - bounds.height() / 4; ++y) {
    for (int x = bounds.left() + bounds.width() / 4; x < bounds.right() - bounds.width() / 4; ++x) {
      const int lightness = QColor(image.pixel(x, y)).lightness();
      darkest = std::min(darkest, lightness);
      lightest = std::max(lightest, lightness);
    }
  }
  EXPECT_GT(lightest - darkest, 20) << "a lit sphere is not flat";
}

TEST_F(MeshViewportTest, ClockwiseMeshRendersLikeCounterClockwise) {
  auto sphere = sc::testing::icosphere(3);
  m_viewport.setMesh(sphere.V, sphere.F);
  const QImage outward = grab();
  const int area = sc::testing::countDifferentPixels(outward, m_background);
  sphere.F.col(1).swap(sphere.F.col(2));
  m_viewport.setMesh(sphere.V, sphere.F);
  const QImage inward = grab();
  // Only the silhouette band (where interpolated normals graze the view direction) may shade differently.
  EXPECT_LT(countPixelsDifferingBy(outward, inward, 3), area / 25);
}

TEST_F(MeshViewportTest, AFewFlippedTrianglesDoNotShowAsDarkSpecks) {
  auto sphere = sc::testing::icosphere(3);
  m_viewport.setMesh(sphere.V, sphere.F);
  const QImage consistent = grab();
  const int area = sc::testing::countDifferentPixels(consistent, m_background);
  for (Eigen::Index f = 0; f < sphere.F.rows(); f += 25) {
    std::swap(sphere.F(f, 1), sphere.F(f, 2));
  }
  m_viewport.setMesh(sphere.V, sphere.F);
  const QImage flipped = grab();
  EXPECT_LT(countPixelsDifferingBy(consistent, flipped, 40), area / 100)
      << "a flipped triangle is shaded with its (outward) vertex normals";
}

TEST_F(MeshViewportTest, SetPositionsUploadsWithoutReframing) {
  const auto sphere = sc::testing::icosphere(3);
  m_viewport.setMesh(sphere.V, sphere.F);
  const int fullArea = sc::testing::countDifferentPixels(grab(), m_background);
  const float distance = m_viewport.camera().distance();
  m_viewport.setPositions(0.5 * sphere.V);
  const int halfArea = sc::testing::countDifferentPixels(grab(), m_background);
  EXPECT_EQ(m_viewport.camera().distance(), distance);
  EXPECT_GT(halfArea, fullArea / 6);
  EXPECT_LT(halfArea, fullArea / 3) << "half the radius covers about a quarter of the pixels";
}

TEST_F(MeshViewportTest, ClearMeshShowsTheBackgroundOnly) {
  const auto sphere = sc::testing::icosphere(2);
  m_viewport.setMesh(sphere.V, sphere.F);
  m_viewport.clearMesh();
  EXPECT_EQ(m_viewport.vertexCount(), 0);
  EXPECT_EQ(grab(), m_background);
}

TEST_F(MeshViewportTest, MouseOrbitsZoomsAndDoubleClickResets) {
  const auto sphere = sc::testing::icosphere(2);
  m_viewport.setMesh(sphere.V, sphere.F);
  const float yaw = m_viewport.camera().yaw();
  const float distance = m_viewport.camera().distance();

  sendMouse(QEvent::MouseButtonPress, {100, 100}, Qt::LeftButton, Qt::LeftButton);
  sendMouse(QEvent::MouseMove, {150, 100}, Qt::NoButton, Qt::LeftButton);
  EXPECT_NE(m_viewport.camera().yaw(), yaw);

  const QPointF centre(160, 120);
  QWheelEvent wheel(centre, m_viewport.mapToGlobal(centre), QPoint(), QPoint(0, 240), Qt::NoButton, Qt::NoModifier,
                    Qt::NoScrollPhase, false);
  QApplication::sendEvent(&m_viewport, &wheel);
  EXPECT_LT(m_viewport.camera().distance(), distance) << "wheel forward zooms in";

  // off the mesh (a corner): re-frames; on the mesh a double click sets the orbit pivot (MeshViewportToolsTest)
  sendMouse(QEvent::MouseButtonDblClick, {2, 2}, Qt::LeftButton, Qt::LeftButton);
  EXPECT_EQ(m_viewport.camera().yaw(), yaw);
  EXPECT_FLOAT_EQ(m_viewport.camera().distance(), distance);
}

// hellogl2 lifetime: moving the widget into another top-level window destroys its context (cleanup()) and
// initializes a new one, into which the mesh must be uploaded again.
TEST(MeshViewport, SurvivesMovingToAnotherWindow) {
  if (!sc::testing::openGlAvailable()) {
    GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
  }
  const auto sphere = sc::testing::icosphere(3);
  auto* viewport = new sc::app::MeshViewport;
  viewport->resize(200, 160);
  viewport->setMesh(sphere.V, sphere.F);
  viewport->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(viewport));
  const QImage before = viewport->grabFramebuffer();

  QWidget window;
  window.resize(200, 160);
  viewport->setParent(&window);  // takes ownership
  viewport->move(0, 0);
  window.show();
  viewport->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  const QImage after = viewport->grabFramebuffer();
  ASSERT_EQ(after.size(), before.size());
  const QPoint centre(after.width() / 2, after.height() / 2);
  EXPECT_NE(after.pixel(centre), after.pixel(0, 0)) << "the mesh is drawn in the new context";
  // Same picture; only antialiased edge pixels may differ slightly between the two contexts' framebuffers.
  EXPECT_LT(countPixelsDifferingBy(before, after, 8), after.width() * after.height() / 100);
}
