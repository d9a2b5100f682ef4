#include "app/gui/orbit_camera.h"

#include <QtMath>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sc::app {

namespace {
constexpr float kDegreesPerPixel = 0.4f;
constexpr float kMaxPitch = 89.0f;
constexpr float kZoomPerStep = 0.85f;
constexpr float kDegrees = 57.29577951308232f;

struct Angles {
  float yaw;
  float pitch;
};

Angles anglesOf(StandardView view) {
  switch (view) {
    case StandardView::Home:
      return {OrbitCamera::kDefaultYaw, OrbitCamera::kDefaultPitch};
    case StandardView::Front:
      return {0.0f, 0.0f};
    case StandardView::Back:
      return {180.0f, 0.0f};
    case StandardView::Left:
      return {-90.0f, 0.0f};
    case StandardView::Right:
      return {90.0f, 0.0f};
    case StandardView::Top:
      return {0.0f, 90.0f};
    case StandardView::Bottom:
      return {0.0f, -90.0f};
  }
  return {OrbitCamera::kDefaultYaw, OrbitCamera::kDefaultPitch};
}
}  // namespace

void OrbitCamera::setSceneBounds(const QVector3D& lo, const QVector3D& hi) {
  QVector3D center = (lo + hi) * 0.5f;
  QVector3D half = (hi - lo) * 0.5f;
  if (!(half.length() > 0.0f) || !std::isfinite(half.length())) {
    center = std::isfinite(center.length()) ? center : QVector3D{};
    half = QVector3D{0.5f, 0.5f, 0.5f};
  }
  m_lo = center - half;
  m_hi = center + half;
  m_sceneRadius = half.length();
}

void OrbitCamera::frame(std::span<const QVector3D> points, std::optional<StandardView> view) {
  m_framePoints.clear();
  if (points.empty()) {
    frame(QVector3D{-0.5f, -0.5f, -0.5f}, QVector3D{0.5f, 0.5f, 0.5f}, view);
    return;
  }
  QVector3D lo = points.front();
  QVector3D hi = points.front();
  for (const QVector3D& p : points) {
    lo = QVector3D{std::min(lo.x(), p.x()), std::min(lo.y(), p.y()), std::min(lo.z(), p.z())};
    hi = QVector3D{std::max(hi.x(), p.x()), std::max(hi.y(), p.y()), std::max(hi.z(), p.z())};
  }
  const std::size_t stride = (points.size() + kMaxFramePoints - 1) / kMaxFramePoints;
  m_framePoints.reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride) {
    m_framePoints.push_back(points[i]);
  }
  setSceneBounds(lo, hi);
  m_target = (m_lo + m_hi) * 0.5f;  // the orbit pivot starts at the box centre; fit() shifts it across the view
  if (view) orient(*view);
  m_fitPending = true;
  fit();
}

void OrbitCamera::orient(StandardView view) {
  const Angles angles = anglesOf(view);
  m_yaw = angles.yaw;
  m_pitch = angles.pitch;
  m_trackball = turntable();
}

void OrbitCamera::setUpAxis(UpAxis axis) {
  m_upAxis = axis;
  orient(StandardView::Home);
  if (!m_framePoints.empty()) {
    m_target = (m_lo + m_hi) * 0.5f;
    m_fitPending = true;
    fit();
  }
}

void OrbitCamera::setRotationMode(RotationMode mode) {
  if (mode == m_mode) return;
  if (mode == RotationMode::Trackball) {
    m_trackball = turntable();
  } else {
    aimFrom(eye() - m_target);  // the eye stays; any roll goes
  }
  m_mode = mode;
}

void OrbitCamera::setPivot(const QVector3D& pivot) {
  // A pan that brings the pivot to the centre of the screen: the eye moves in its view plane only.
  const QVector3D back = rotation().transposed().map(QVector3D{0.0f, 0.0f, 1.0f});
  const float depth = QVector3D::dotProduct(eye() - pivot, back);
  m_target = pivot;
  m_distance = std::clamp(depth, 1e-3f * m_sceneRadius, 100.0f * m_sceneRadius);
  m_fitPending = false;
}

void OrbitCamera::aimFrom(const QVector3D& back) {
  const float length = back.length();
  if (!(length > 0.0f)) return;
  const QVector3D d = upSpace().rotatedVector(back / length);
  m_pitch = std::clamp(std::asin(std::clamp(d.y(), -1.0f, 1.0f)) * kDegrees, -kMaxPitch, kMaxPitch);
  m_yaw = std::atan2(d.x(), d.z()) * kDegrees;
  m_trackball = turntable();
}

void OrbitCamera::frame(const QVector3D& lo, const QVector3D& hi, std::optional<StandardView> view) {
  std::vector<QVector3D> corners;
  for (int c = 0; c < 8; ++c) {
    corners.emplace_back((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
  }
  frame(corners, view);
}

void OrbitCamera::setViewportSize(int width, int height) {
  m_width = std::max(width, 1);
  m_height = std::max(height, 1);
  if (m_fitPending) {
    fit();
  }
}

void OrbitCamera::orbit(float dxPixels, float dyPixels) {
  m_fitPending = false;
  if (m_mode == RotationMode::Trackball) {
    const float pixels = std::hypot(dxPixels, dyPixels);
    if (!(pixels > 0.0f)) return;
    // The scene turns about the camera axis perpendicular to the drag (the turntable's yaw and pitch directions).
    m_trackball =
        (QQuaternion::fromAxisAndAngle(QVector3D{dyPixels, dxPixels, 0.0f} / pixels, pixels * kDegreesPerPixel) *
         m_trackball)
            .normalized();
    const QVector3D d = m_trackball.conjugated().rotatedVector({0.0f, 0.0f, 1.0f});  // the eye, up space
    m_pitch = std::asin(std::clamp(d.y(), -1.0f, 1.0f)) * kDegrees;
    m_yaw = std::atan2(d.x(), d.z()) * kDegrees;
    return;
  }
  m_yaw -= dxPixels * kDegreesPerPixel;
  m_yaw = std::remainder(m_yaw, 360.0f);
  m_pitch = std::clamp(m_pitch + dyPixels * kDegreesPerPixel, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(float dxPixels, float dyPixels) {
  const float unitsPerPixel =
      2.0f * m_distance * std::tan(qDegreesToRadians(kFieldOfViewY) * 0.5f) / static_cast<float>(m_height);
  const QMatrix4x4 r = rotation();
  // Rows of the world-to-camera rotation are the camera axes in world coordinates.
  const QVector3D right = r.row(0).toVector3D();
  const QVector3D up = r.row(1).toVector3D();
  m_target += (-dxPixels * right + dyPixels * up) * unitsPerPixel;
  m_fitPending = false;
}

void OrbitCamera::zoom(float steps) {
  const float factor = std::pow(kZoomPerStep, steps);
  m_distance = std::clamp(m_distance * factor, 1e-3f * m_sceneRadius, 100.0f * m_sceneRadius);
  m_fitPending = false;
}

QQuaternion OrbitCamera::turntable() const {
  // Up-space-to-camera rotation Rx(pitch) Ry(-yaw): it maps the eye direction (seen from the target) to +z without
  // roll, so the camera looks down its -z axis with the up axis projecting upwards.
  return QQuaternion::fromAxisAndAngle(1.0f, 0.0f, 0.0f, m_pitch) *
         QQuaternion::fromAxisAndAngle(0.0f, 1.0f, 0.0f, -m_yaw);
}

QQuaternion OrbitCamera::upSpace() const {
  // z up: Rx(-90°) maps (x, y, z) to (x, z, -y), world +z to +y.
  return m_upAxis == UpAxis::Z ? QQuaternion::fromAxisAndAngle(1.0f, 0.0f, 0.0f, -90.0f) : QQuaternion();
}

QMatrix4x4 OrbitCamera::rotation() const {
  const QQuaternion camera = m_mode == RotationMode::Trackball ? m_trackball : turntable();
  QMatrix4x4 r;
  r.rotate(camera * upSpace());
  return r;
}

QVector3D OrbitCamera::eye() const {
  const QVector3D back = rotation().transposed().map(QVector3D{0.0f, 0.0f, 1.0f});
  return m_target + m_distance * back;
}

QVector3D OrbitCamera::up() const { return rotation().transposed().map(QVector3D{0.0f, 1.0f, 0.0f}); }

void OrbitCamera::lookAt(const QVector3D& eye, const QVector3D& target) {
  m_target = target;
  const QVector3D back = eye - target;
  const float length = back.length();
  if (length > 0.0f) {
    aimFrom(back);
    m_distance = std::clamp(length, 1e-3f * m_sceneRadius, 100.0f * m_sceneRadius);
  }
  m_fitPending = false;
}

QMatrix4x4 OrbitCamera::view() const {
  QMatrix4x4 v;
  v.translate(0.0f, 0.0f, -m_distance);
  v *= rotation();
  v.translate(-m_target);
  return v;
}

QMatrix4x4 OrbitCamera::projection() const {
  const QVector3D center = (m_lo + m_hi) * 0.5f;
  const float eyeToCenter = (eye() - center).length();
  const float nearPlane = std::max(eyeToCenter - 1.05f * m_sceneRadius, 1e-3f * m_sceneRadius);
  const float farPlane = eyeToCenter + 1.05f * m_sceneRadius;
  QMatrix4x4 p;
  p.perspective(kFieldOfViewY, aspect(), nearPlane, farPlane);
  return p;
}

void OrbitCamera::fit() {
  // In camera axes relative to the current target, a point q seen from an eye at distance d, with the target
  // shifted by c across the view, is inside the horizontal half-angle when |q.x - c| <= t (d - q.z), t = tan.
  // Both inequalities hold iff  c - t d <= U = min(q.x - t q.z)  and  -c - t d <= W = min(-q.x - t q.z).
  // The smallest d is -(U + W) / (2t), at c = (U - W) / 2; the same c centres the extremes for any larger d.
  // Solving x and y separately and taking the larger d centres and fits exactly in perspective.
  if (m_framePoints.empty()) {
    return;
  }
  const float tanY = std::tan(qDegreesToRadians(kFieldOfViewY) * 0.5f) * kFillFraction;
  const float tanX = tanY * aspect();
  const QMatrix4x4 r = rotation();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float ux = kInf, wx = kInf, uy = kInf, wy = kInf, maxDepth = -kInf;
  for (const QVector3D& p : m_framePoints) {
    const QVector3D q = r.map(p - m_target);
    ux = std::min(ux, q.x() - tanX * q.z());
    wx = std::min(wx, -q.x() - tanX * q.z());
    uy = std::min(uy, q.y() - tanY * q.z());
    wy = std::min(wy, -q.y() - tanY * q.z());
    maxDepth = std::max(maxDepth, q.z());
  }
  const QVector3D shift{(ux - wx) * 0.5f, (uy - wy) * 0.5f, 0.0f};
  m_target += r.transposed().map(shift);
  const float d = std::max({-(ux + wx) / (2.0f * tanX), -(uy + wy) / (2.0f * tanY), maxDepth});
  m_distance = std::max(d, 1e-3f * m_sceneRadius) + 1e-3f * m_sceneRadius;
}

}  // namespace sc::app
