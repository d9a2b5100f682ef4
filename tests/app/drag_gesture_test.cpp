// Tests for src/app/gui/drag_gesture.cpp: mouse motion → view-plane translation and view-axis rotation (pure).

#include "app/gui/drag_gesture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

// A camera at (0, 0, 5) looking at the origin, 30° vertical field of view, 100 × 100 pixels.
struct Camera {
  QMatrix4x4 view;
  QMatrix4x4 projection;
  QSizeF size{100, 100};
  Camera() {
    view.lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
    projection.perspective(30.0f, 1.0f, 1.0f, 20.0f);
  }
};

double worldPerPixel(double distance) { return 2.0 * distance * std::tan(15.0 * std::numbers::pi / 180.0) / 100.0; }

}  // namespace

TEST(DragGesture, ViewPlaneDeltaFollowsTheCursor) {
  const Camera c;
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const Eigen::Vector3d right = sc::app::viewPlaneDelta(c.view, c.projection, c.size, origin, {10, 0});
  EXPECT_NEAR(right.x(), 10 * worldPerPixel(5), 1e-4);
  EXPECT_NEAR(right.y(), 0, 1e-5);
  EXPECT_NEAR(right.z(), 0, 1e-4) << "stays in the view plane";
  const Eigen::Vector3d up = sc::app::viewPlaneDelta(c.view, c.projection, c.size, origin, {0, -10});
  EXPECT_NEAR(up.y(), 10 * worldPerPixel(5), 1e-4) << "screen y grows downwards";
  const Eigen::Vector3d far = sc::app::viewPlaneDelta(c.view, c.projection, c.size, {0, 0, -5}, {10, 0});
  EXPECT_NEAR(far.norm(), 2.0 * right.norm(), 1e-4) << "twice as far: twice the world distance";
  const Eigen::Vector3d twice = sc::app::viewPlaneDelta(c.view, c.projection, c.size, origin, {20, 0});
  EXPECT_NEAR(twice.norm(), 2.0 * right.norm(), 1e-4) << "linear in the mouse distance";
}

TEST(DragGesture, TranslationAccumulatesAndRotationStaysIdentity) {
  const Camera c;
  sc::app::DragGesture drag(c.view, c.projection, c.size, Eigen::Vector3d::Zero(), {50, 50});
  drag.moveTo({60, 50}, false);
  drag.moveTo({60, 40}, false);
  EXPECT_NEAR(drag.translation().x(), 10 * worldPerPixel(5), 1e-4);
  EXPECT_NEAR(drag.translation().y(), 10 * worldPerPixel(5), 1e-4);
  EXPECT_TRUE(drag.rotation().isIdentity(1e-12));
}

TEST(DragGesture, CounterClockwiseOnScreenRotatesAboutTheViewAxis) {
  const Camera c;
  // The centroid projects to the screen centre; the cursor sweeps from its right to above it: +90° on screen.
  sc::app::DragGesture drag(c.view, c.projection, c.size, Eigen::Vector3d::Zero(), {70, 50});
  drag.moveTo({50, 30}, true);
  const Eigen::Vector3d x = drag.rotation() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x.x(), 0, 1e-5);
  EXPECT_NEAR(x.y(), 1, 1e-5) << "x turns into y: counter-clockwise seen from the eye at +z";
  EXPECT_NEAR((drag.rotation() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm(), 0, 1e-6)
      << "the view axis is fixed";
  EXPECT_TRUE(drag.translation().isZero());
  // Translating afterwards adds to t and keeps R.
  drag.moveTo({60, 30}, false);
  EXPECT_GT(drag.translation().x(), 0);
  EXPECT_NEAR((drag.rotation() * Eigen::Vector3d::UnitX()).y(), 1, 1e-5);
}
