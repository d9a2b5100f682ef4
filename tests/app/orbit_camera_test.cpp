// Tests for src/app/gui/orbit_camera.cpp (pure math, no GL).

#include "app/gui/orbit_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

using sc::app::OrbitCamera;

namespace {

QVector3D toNdc(const OrbitCamera& camera, const QVector3D& p) { return (camera.projection() * camera.view()).map(p); }

std::array<QVector3D, 8> corners(const QVector3D& lo, const QVector3D& hi) {
  std::array<QVector3D, 8> result;
  for (int c = 0; c < 8; ++c) {
    result[static_cast<std::size_t>(c)] = {(c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                                           (c & 4) ? hi.z() : lo.z()};
  }
  return result;
}

// Largest |x| or |y| in NDC over the box corners, after checking that every corner is inside the frustum.
float checkInsideAndGetSpan(const OrbitCamera& camera, const QVector3D& lo, const QVector3D& hi) {
  float span = 0.0f;
  for (const QVector3D& p : corners(lo, hi)) {
    const QVector3D ndc = toNdc(camera, p);
    EXPECT_LE(std::abs(ndc.x()), 1.0001f) << "corner outside the view horizontally";
    EXPECT_LE(std::abs(ndc.y()), 1.0001f) << "corner outside the view vertically";
    EXPECT_LE(std::abs(ndc.z()), 1.0001f) << "corner outside the depth range";
    span = std::max({span, std::abs(ndc.x()), std::abs(ndc.y())});
  }
  return span;
}

}  // namespace

TEST(OrbitCamera, FramedBoxFillsViewForAnyShapeAndAspect) {
  const std::array<std::array<QVector3D, 2>, 3> boxes{{{QVector3D(-1, -1, -1), QVector3D(1, 1, 1)},
                                                       {QVector3D(10, 0, 0), QVector3D(14, 1, 0.5f)},
                                                       {QVector3D(0, 0, 0), QVector3D(0.01f, 0.3f, 0.02f)}}};
  for (const auto& box : boxes) {
    for (const auto& size : {std::array{800, 600}, std::array{200, 900}, std::array{1000, 100}}) {
      OrbitCamera camera;
      camera.setViewportSize(size[0], size[1]);
      camera.frame(box[0], box[1]);
      const float span = checkInsideAndGetSpan(camera, box[0], box[1]);
      EXPECT_GT(span, 0.85f) << "the framed box should nearly fill the tighter axis";
    }
  }
}

TEST(OrbitCamera, RefitsOnResizeUntilTheUserMoves) {
  const QVector3D lo(-2, -1, -1);
  const QVector3D hi(2, 1, 1);
  OrbitCamera camera;
  camera.frame(lo, hi);  // before the widget knows its size
  camera.setViewportSize(300, 900);
  checkInsideAndGetSpan(camera, lo, hi);
  camera.orbit(10, 0);
  const float distance = camera.distance();
  camera.setViewportSize(900, 300);
  EXPECT_EQ(camera.distance(), distance) << "a user-chosen view is kept on resize";
}

TEST(OrbitCamera, OrbitKeepsTargetAndDistanceAndClampsPitch) {
  OrbitCamera camera;
  camera.setViewportSize(400, 300);
  camera.frame(QVector3D(0, 0, 0), QVector3D(2, 2, 2));
  const QVector3D target = camera.target();
  const float distance = camera.distance();
  camera.orbit(123, -45);
  EXPECT_EQ(camera.target(), target);
  EXPECT_NEAR((camera.eye() - target).length(), distance, 1e-4f * distance);
  EXPECT_NE(camera.yaw(), OrbitCamera::kDefaultYaw);
  camera.orbit(0, 10000);
  EXPECT_LE(camera.pitch(), 89.0f);
  camera.orbit(0, -20000);
  EXPECT_GE(camera.pitch(), -89.0f);
  // The target stays at the centre of the image.
  const QVector3D ndc = toNdc(camera, target);
  EXPECT_NEAR(ndc.x(), 0.0f, 1e-5f);
  EXPECT_NEAR(ndc.y(), 0.0f, 1e-5f);
}

TEST(OrbitCamera, ZoomStepsAreInverse) {
  OrbitCamera camera;
  camera.setViewportSize(400, 300);
  camera.frame(QVector3D(-1, -1, -1), QVector3D(1, 1, 1));
  const float distance = camera.distance();
  camera.zoom(2.0f);
  EXPECT_LT(camera.distance(), distance);
  camera.zoom(-2.0f);
  EXPECT_NEAR(camera.distance(), distance, 1e-4f * distance);
  camera.zoom(1000.0f);
  EXPECT_GT(camera.distance(), 0.0f) << "zoom is clamped";
}

TEST(OrbitCamera, PanMovesTheSceneWithTheCursor) {
  OrbitCamera camera;
  camera.setViewportSize(400, 300);
  camera.frame(QVector3D(-1, -1, -1), QVector3D(1, 1, 1));
  const QVector3D oldTarget = camera.target();
  camera.pan(40.0f, 30.0f);  // drag right and down (screen y grows downwards)
  const QVector3D ndc = toNdc(camera, oldTarget);
  EXPECT_GT(ndc.x(), 0.05f) << "the old centre moves right";
  EXPECT_LT(ndc.y(), -0.05f) << "the old centre moves down";
  // One pixel of drag moves the target's plane by one pixel: 40 px of 400 = 0.2 NDC.
  EXPECT_NEAR(ndc.x(), 0.2f, 1e-3f);
  EXPECT_NEAR(ndc.y(), -0.2f, 1e-3f);
}
