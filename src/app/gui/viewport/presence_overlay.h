#pragma once
// PresenceOverlay: the other users' presence over MeshViewport's picture (issue 15): each user's camera as a small
// pyramid (apex at the eye, opening towards the target, a tick on its up side) with the user's name, each pointer
// as a dot on the surface, each painted handle as a ring ("NAME's handle"), and "NAME is dragging" labels in the
// top-left corner, all in the user's colour. Drawn with QPainter after the GL passes (like ViewportInput's overlay):
// lines projected by the view's camera, clipped at the near plane, not depth-tested. Markers are in the viewport's
// coordinates (the mesh's, less its origin). Cost: O(markers) per paint; nothing when there are none.

#include <QColor>
#include <QMatrix4x4>
#include <QPointF>
#include <QSize>
#include <QString>
#include <QVector3D>

#include <optional>
#include <span>
#include <utility>
#include <vector>

class QPainter;

namespace sc::app {

/// One remote user as drawn.
struct PresenceMarker {
  quint32 peerId = 0;
  QString name;
  QColor color;
  QVector3D eye;
  QVector3D target;
  QVector3D up{0.0f, 1.0f, 0.0f};
  std::optional<QVector3D> pointer;  ///< on the surface
  bool dragging = false;
  std::optional<QVector3D> handle;  ///< the centroid of the user's painted handle
  friend bool operator==(const PresenceMarker&, const PresenceMarker&) = default;
};

using Segment = std::pair<QVector3D, QVector3D>;

/// The camera marker's edges: 4 from the apex (the eye) to the corners of a 4:3 rectangle at `size` along the
/// view direction (towards the target), its 4 sides, and 2 forming a tick above its up side. Empty when eye ==
/// target or up is parallel to the view direction (falls back to world +y, then +z, first). Pure.
[[nodiscard]] std::vector<Segment> cameraMarkerSegments(const QVector3D& eye, const QVector3D& target,
                                                        const QVector3D& up, float size);

/// The surface point under `cursor` (widget pixels): among the vertices whose projection lies within `radius`
/// pixels of it, the one nearest the eye; nullopt when none. `xyz` is 3·#V floats in the view's coordinates.
/// Approximates the visible surface by its vertices (no depth buffer). Cost: O(#V).
[[nodiscard]] std::optional<QVector3D> surfacePointUnder(std::span<const float> xyz, const QMatrix4x4& view,
                                                         const QMatrix4x4& projection, QSize widget, QPointF cursor,
                                                         float radius);

class PresenceOverlay {
 public:
  /// Fraction of the scene's bounding-box diagonal that a camera marker's depth measures.
  static constexpr float kMarkerScale = 0.12f;

  void setMarkers(std::vector<PresenceMarker> markers) { m_markers = std::move(markers); }
  [[nodiscard]] const std::vector<PresenceMarker>& markers() const { return m_markers; }

  /// Draws the markers onto `painter` (a widget of logical size `widget`) seen through view·projection; markers
  /// measure kMarkerScale · `sceneDiagonal`.
  void paint(QPainter& painter, const QMatrix4x4& view, const QMatrix4x4& projection, QSize widget,
             float sceneDiagonal) const;

 private:
  std::vector<PresenceMarker> m_markers;
};

}  // namespace sc::app
