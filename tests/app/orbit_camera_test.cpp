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

// --- issue 16, viewer habits: up axis, standard views, trackball, pivot

namespace {

using sc::app::RotationMode;
using sc::app::StandardView;
using sc::app::UpAxis;

QVector3D eyeDirection(const OrbitCamera& camera) { return (camera.eye() - camera.target()).normalized(); }

void expectNear(const QVector3D& a, const QVector3D& b, float tolerance, const char* what) {
  EXPECT_LE((a - b).length(), tolerance) << what << ": (" << a.x() << ", " << a.y() << ", " << a.z() << ") vs ("
                                         << b.x() << ", " << b.y() << ", " << b.z() << ")";
}

}  // namespace

TEST(OrbitCamera, HomeViewLooksFromTheFrontAndAboveForEitherUpAxis) {
  for (const UpAxis axis : {UpAxis::Y, UpAxis::Z}) {
    OrbitCamera camera;
    camera.setViewportSize(400, 300);
    camera.setUpAxis(axis);
    camera.frame(QVector3D(-1, -1, -1), QVector3D(1, 1, 1));
    const QVector3D up = axis == UpAxis::Y ? QVector3D(0, 1, 0) : QVector3D(0, 0, 1);
    const QVector3D front = axis == UpAxis::Y ? QVector3D(0, 0, 1) : QVector3D(0, -1, 0);
    const QVector3D d = eyeDirection(camera);
    EXPECT_NEAR(QVector3D::dotProduct(d, up), std::sin(OrbitCamera::kDefaultPitch * 3.14159265f / 180.0f), 1e-4f)
        << "the eye is above the mesh";
    EXPECT_GT(QVector3D::dotProduct(d, front), 0.7f) << "the eye is in front of the mesh";
    EXPECT_GT(QVector3D::dotProduct(camera.up(), up), 0.9f) << "the up axis points up on screen";
    // the up axis projects straight up: its screen x component is zero (no roll)
    const QVector3D top = toNdc(camera, camera.target() + 0.1f * up) - toNdc(camera, camera.target());
    EXPECT_NEAR(top.x(), 0.0f, 1e-5f);
    EXPECT_GT(top.y(), 0.0f);
  }
}

TEST(OrbitCamera, StandardViewsLookAlongTheAxesAndFit) {
  struct Case {
    StandardView view;
    QVector3D eyeY, eyeZ;  // the eye's direction for y up and for z up
  };
  const Case cases[] = {{StandardView::Front, {0, 0, 1}, {0, -1, 0}}, {StandardView::Back, {0, 0, -1}, {0, 1, 0}},
                        {StandardView::Right, {1, 0, 0}, {1, 0, 0}},  {StandardView::Left, {-1, 0, 0}, {-1, 0, 0}},
                        {StandardView::Top, {0, 1, 0}, {0, 0, 1}},    {StandardView::Bottom, {0, -1, 0}, {0, 0, -1}}};
  const QVector3D lo(-1, -2, -0.5f);
  const QVector3D hi(3, 1, 0.5f);
  for (const UpAxis axis : {UpAxis::Y, UpAxis::Z}) {
    for (const Case& c : cases) {
      OrbitCamera camera;
      camera.setViewportSize(640, 480);
      camera.setUpAxis(axis);
      camera.frame(lo, hi, c.view);
      expectNear(eyeDirection(camera), axis == UpAxis::Y ? c.eyeY : c.eyeZ, 1e-4f, "eye direction");
      EXPECT_GT(checkInsideAndGetSpan(camera, lo, hi), 0.85f) << "the box is framed";
      if (c.view == StandardView::Front) {
        expectNear(camera.up(), axis == UpAxis::Y ? QVector3D(0, 1, 0) : QVector3D(0, 0, 1), 1e-4f, "front's up");
      }
      if (c.view == StandardView::Top) {  // the front at the bottom of the screen: the back points up
        expectNear(camera.up(), axis == UpAxis::Y ? QVector3D(0, 0, -1) : QVector3D(0, 1, 0), 1e-4f, "top's up");
      }
    }
  }
  // nullopt keeps the direction ("fit")
  OrbitCamera camera;
  camera.setViewportSize(640, 480);
  camera.frame(lo, hi, StandardView::Right);
  camera.orbit(30, 20);
  const QVector3D before = eyeDirection(camera);
  camera.frame(lo, hi, std::nullopt);
  expectNear(eyeDirection(camera), before, 1e-5f, "fit keeps the direction");
  EXPECT_GT(checkInsideAndGetSpan(camera, lo, hi), 0.85f);
}

TEST(OrbitCamera, TrackballRotationKeepsThePivotDistanceAndGoesOverThePole) {
  OrbitCamera camera;
  camera.setViewportSize(400, 300);
  camera.frame(QVector3D(-1, -1, -1), QVector3D(1, 1, 1), StandardView::Front);
  camera.setRotationMode(RotationMode::Trackball);
  const QVector3D target = camera.target();
  const float distance = camera.distance();
  const QVector3D start = eyeDirection(camera);
  camera.orbit(0, 300);  // 120 degrees about the screen's x axis: the turntable would stop at 89
  EXPECT_EQ(camera.target(), target);
  EXPECT_NEAR((camera.eye() - target).length(), distance, 1e-4f * distance);
  EXPECT_NEAR(QVector3D::dotProduct(eyeDirection(camera), start), std::cos(120.0f * 3.14159265f / 180.0f), 1e-4f);
  camera.orbit(57, -23);
  camera.orbit(-140, 91);
  EXPECT_EQ(camera.target(), target);
  EXPECT_NEAR((camera.eye() - target).length(), distance, 1e-4f * distance);
  const QVector3D ndc = toNdc(camera, target);
  EXPECT_NEAR(ndc.x(), 0.0f, 1e-5f);
  EXPECT_NEAR(ndc.y(), 0.0f, 1e-5f);
  // Back to the turntable: the eye stays, any roll goes (the up axis projects straight up again).
  const QVector3D eye = camera.eye();
  camera.setRotationMode(RotationMode::Turntable);
  expectNear(camera.eye(), eye, 1e-3f * distance, "the eye stays");
  const QVector3D top = toNdc(camera, target + QVector3D(0, 0.1f, 0)) - toNdc(camera, target);
  EXPECT_NEAR(top.x(), 0.0f, 1e-4f);
}

TEST(OrbitCamera, TrackballAndTurntableAgreeOnAPureHorizontalDrag) {
  OrbitCamera turntable;
  OrbitCamera trackball;
  for (OrbitCamera* camera : {&turntable, &trackball}) {
    camera->setViewportSize(400, 300);
    camera->frame(QVector3D(-1, -1, -1), QVector3D(1, 1, 1), StandardView::Front);
  }
  trackball.setRotationMode(RotationMode::Trackball);
  turntable.orbit(50, 0);
  trackball.orbit(50, 0);
  expectNear(trackball.eye(), turntable.eye(), 1e-4f, "same eye");
  expectNear(trackball.up(), turntable.up(), 1e-4f, "same up");
}

TEST(OrbitCamera, SetPivotCentresThePointKeepingTheOrientation) {
  OrbitCamera camera;
  camera.setViewportSize(400, 300);
  camera.frame(QVector3D(-1, -1, -1), QVector3D(1, 1, 1));
  camera.orbit(40, 10);
  const QVector3D pivot(0.8f, -0.6f, 0.9f);
  const QVector3D direction = eyeDirection(camera);
  const QVector3D up = camera.up();
  const float depth = -camera.view().map(pivot).z();  // the pivot's distance along the view axis
  ASSERT_GT(toNdc(camera, pivot).toVector2D().length(), 0.1f) << "the pivot starts off-centre";
  camera.setPivot(pivot);
  EXPECT_EQ(camera.target(), pivot);
  const QVector3D ndc = toNdc(camera, pivot);
  EXPECT_NEAR(ndc.x(), 0.0f, 1e-5f);
  EXPECT_NEAR(ndc.y(), 0.0f, 1e-5f);
  expectNear(eyeDirection(camera), direction, 1e-5f, "orientation kept");
  expectNear(camera.up(), up, 1e-5f, "no roll");
  EXPECT_NEAR(camera.distance(), depth, 1e-4f * depth) << "the pivot keeps its depth (a pan, no zoom)";
  // orbiting now turns about the pivot
  camera.orbit(80, -30);
  EXPECT_NEAR(toNdc(camera, pivot).x(), 0.0f, 1e-5f);
  EXPECT_NEAR((camera.eye() - pivot).length(), depth, 1e-4f * depth);
}
