#include "app/gui/viewport/presence_overlay.h"

#include <QCoreApplication>
#include <QFontMetrics>
#include <QPainter>
#include <QPainterPath>
#include <QVector4D>

#include <algorithm>
#include <cmath>

namespace sc::app {
namespace {

constexpr float kMinW = 1e-4f;  // clip-space w below which a point is behind the eye

QPointF toWidget(const QVector4D& clip, QSize widget) {
  const float x = clip.x() / clip.w();
  const float y = clip.y() / clip.w();
  return {(0.5 * x + 0.5) * widget.width(), (0.5 - 0.5 * y) * widget.height()};
}

/// The part of a segment in front of the eye, in widget pixels; nullopt when all of it is behind.
std::optional<std::pair<QPointF, QPointF>> projectSegment(const QMatrix4x4& viewProjection, const Segment& segment,
                                                          QSize widget) {
  QVector4D a = viewProjection.map(QVector4D(segment.first, 1.0f));
  QVector4D b = viewProjection.map(QVector4D(segment.second, 1.0f));
  if (a.w() < kMinW && b.w() < kMinW) return std::nullopt;
  if (a.w() < kMinW) std::swap(a, b);
  if (b.w() < kMinW) b = a + (b - a) * ((a.w() - kMinW) / (a.w() - b.w()));
  return std::pair{toWidget(a, widget), toWidget(b, widget)};
}

std::optional<QPointF> projectPoint(const QMatrix4x4& viewProjection, const QVector3D& point, QSize widget) {
  const QVector4D clip = viewProjection.map(QVector4D(point, 1.0f));
  if (clip.w() < kMinW) return std::nullopt;
  return toWidget(clip, widget);
}

/// A label at `at`; one that would leave the `widget` on the right goes left of `at` instead (by `flip` more).
void drawLabel(QPainter& painter, QPointF at, const QString& text, const QColor& color, QSize widget = {},
               qreal flip = 0.0) {
  QRectF box = QRectF(painter.fontMetrics().boundingRect(text)).adjusted(-5, -2, 5, 2).translated(at);
  if (widget.isValid() && box.right() > widget.width()) box.moveRight(at.x() - flip);
  painter.setPen(Qt::NoPen);
  painter.setBrush(QColor(255, 255, 255, 210));
  painter.drawRoundedRect(box, 4, 4);
  painter.setPen(color.darker(130));
  painter.drawText(box, Qt::AlignCenter, text);
}

}  // namespace

std::vector<Segment> cameraMarkerSegments(const QVector3D& eye, const QVector3D& target, const QVector3D& up,
                                          float size) {
  const QVector3D forward = (target - eye).normalized();
  if (forward.isNull() || !(size > 0.0f)) return {};
  QVector3D right;
  for (const QVector3D& candidate : {up, QVector3D(0, 1, 0), QVector3D(0, 0, 1)}) {
    right = QVector3D::crossProduct(forward, candidate);
    if (right.length() > 1e-3f * candidate.length()) break;
  }
  right.normalize();
  const QVector3D upward = QVector3D::crossProduct(right, forward);
  const QVector3D centre = eye + forward * size;
  const QVector3D halfWidth = right * (0.5f * size);
  const QVector3D halfHeight = upward * (0.375f * size);
  const QVector3D corners[4] = {centre - halfWidth - halfHeight, centre + halfWidth - halfHeight,
                                centre + halfWidth + halfHeight, centre - halfWidth + halfHeight};
  std::vector<Segment> segments;
  for (int i = 0; i < 4; ++i) {
    segments.emplace_back(eye, corners[i]);
    segments.emplace_back(corners[i], corners[(i + 1) % 4]);
  }
  const QVector3D tip = centre + halfHeight * 1.8f;
  segments.emplace_back(corners[3] + 0.4f * (corners[2] - corners[3]), tip);
  segments.emplace_back(tip, corners[2] + 0.4f * (corners[3] - corners[2]));
  return segments;
}

std::optional<QVector3D> surfacePointUnder(std::span<const float> xyz, const QMatrix4x4& view,
                                           const QMatrix4x4& projection, QSize widget, QPointF cursor, float radius) {
  const QMatrix4x4 viewProjection = projection * view;
  const double r2 = double(radius) * radius;
  std::optional<QVector3D> best;
  float bestW = 0.0f;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) {
    const QVector3D p{xyz[i], xyz[i + 1], xyz[i + 2]};
    const QVector4D clip = viewProjection.map(QVector4D(p, 1.0f));
    if (clip.w() < kMinW || (best && clip.w() >= bestW)) continue;  // behind the eye, or farther than the best
    const QPointF d = toWidget(clip, widget) - cursor;
    if (d.x() * d.x() + d.y() * d.y() > r2) continue;
    best = p;
    bestW = clip.w();  // the eye distance (perspective: w = −z_eye)
  }
  return best;
}

void PresenceOverlay::paint(QPainter& painter, const QMatrix4x4& view, const QMatrix4x4& projection, QSize widget,
                            float sceneDiagonal) const {
  if (m_markers.empty()) return;
  const QMatrix4x4 viewProjection = projection * view;
  painter.setRenderHint(QPainter::Antialiasing);
  const float size = kMarkerScale * sceneDiagonal;
  int draggingRow = 0;
  for (const PresenceMarker& marker : m_markers) {
    painter.setPen(QPen(marker.color, 2.0));
    painter.setBrush(Qt::NoBrush);
    for (const Segment& segment : cameraMarkerSegments(marker.eye, marker.target, marker.up, size)) {
      if (const auto line = projectSegment(viewProjection, segment, widget))
        painter.drawLine(line->first, line->second);
    }
    if (const auto eye = projectPoint(viewProjection, marker.eye, widget)) {
      drawLabel(painter, *eye + QPointF(8, -20), marker.name, marker.color);
    }
    if (marker.pointer) {
      if (const auto at = projectPoint(viewProjection, *marker.pointer, widget)) {
        painter.setPen(QPen(Qt::white, 2.0));
        painter.setBrush(marker.color);
        painter.drawEllipse(*at, 6.0, 6.0);
      }
    }
    if (marker.handle) {  // a ring in the user's colour, named: where their handle is
      if (const auto at = projectPoint(viewProjection, *marker.handle, widget)) {
        painter.setPen(QPen(marker.color, 3.0));
        painter.setBrush(Qt::NoBrush);
        painter.drawEllipse(*at, 14.0, 14.0);
        const QString text = QCoreApplication::translate("PresenceOverlay", "%1's handle").arg(marker.name);
        drawLabel(painter, *at + QPointF(18, -8), text, marker.color, widget, 36.0);
      }
    }
    if (marker.dragging) {
      const QString text = QCoreApplication::translate("PresenceOverlay", "%1 is dragging").arg(marker.name);
      drawLabel(painter, QPointF(12, 24 + 24 * draggingRow++), text, marker.color);
    }
  }
}

}  // namespace sc::app
