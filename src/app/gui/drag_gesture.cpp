#include "app/gui/drag_gesture.h"

#include <Eigen/Geometry>

#include <QVector4D>

#include <cmath>

namespace sc::app {

namespace {

QVector4D homogeneous(const Eigen::Vector3d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), 1.0f};
}

}  // namespace

Eigen::Vector3d viewPlaneDelta(const QMatrix4x4& view, const QMatrix4x4& projection, QSizeF viewport,
                               const Eigen::Vector3d& point, QPointF deltaPixels) {
  const QMatrix4x4 viewProjection = projection * view;
  bool invertible = false;
  const QMatrix4x4 inverse = viewProjection.inverted(&invertible);
  const QVector4D clip = viewProjection.map(homogeneous(point));
  if (!invertible || clip.w() <= 0.0f || viewport.isEmpty()) {
    return Eigen::Vector3d::Zero();
  }
  // === shift in NDC (y flips: screen y grows downwards), keep NDC depth, unproject.
  const QVector4D ndc = clip / clip.w();
  const QVector4D shifted(ndc.x() + static_cast<float>(2.0 * deltaPixels.x() / viewport.width()),
                          ndc.y() - static_cast<float>(2.0 * deltaPixels.y() / viewport.height()), ndc.z(), 1.0f);
  const QVector4D a = inverse.map(ndc);
  const QVector4D b = inverse.map(shifted);
  const QVector4D delta = b / b.w() - a / a.w();
  return {delta.x(), delta.y(), delta.z()};
}

DragGesture::DragGesture(const QMatrix4x4& view, const QMatrix4x4& projection, QSizeF viewport,
                         const Eigen::Vector3d& centroid, QPointF start)
    : m_view(view), m_projection(projection), m_viewport(viewport), m_centroid(centroid), m_last(start) {}

QPointF DragGesture::toScreen(const Eigen::Vector3d& point) const {
  const QVector4D clip = (m_projection * m_view).map(homogeneous(point));
  const float w = clip.w() > 0.0f ? clip.w() : 1.0f;
  return {(clip.x() / w * 0.5 + 0.5) * m_viewport.width(), (0.5 - clip.y() / w * 0.5) * m_viewport.height()};
}

void DragGesture::moveTo(QPointF pos, bool rotate) {
  const Eigen::Vector3d current = m_centroid + m_translation;
  if (!rotate) {
    m_translation += viewPlaneDelta(m_view, m_projection, m_viewport, current, pos - m_last);
    m_last = pos;
    return;
  }
  // === the angle swept around the centroid's projection, measured with y up (counter-clockwise positive).
  const QPointF centre = toScreen(current);
  const Eigen::Vector2d from(m_last.x() - centre.x(), centre.y() - m_last.y());
  const Eigen::Vector2d to(pos.x() - centre.x(), centre.y() - pos.y());
  m_last = pos;
  if (from.norm() < 1e-6 || to.norm() < 1e-6) {
    return;  // the cursor sits on the pivot: no defined angle
  }
  const double angle = std::atan2(from.x() * to.y() - from.y() * to.x(), from.dot(to));
  // The eye's +z axis (towards the viewer) in world coordinates is the third row of the view rotation.
  const Eigen::Vector3d axis = Eigen::Vector3d(m_view(2, 0), m_view(2, 1), m_view(2, 2)).normalized();
  m_rotation = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * m_rotation;
}

}  // namespace sc::app
