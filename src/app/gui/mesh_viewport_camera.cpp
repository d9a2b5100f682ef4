// MeshViewport: the camera's view habits (standard views, up axis, the double click's pivot). The camera math is
// OrbitCamera's; this file only feeds it the mesh's current vertices and repaints.

#include "app/gui/mesh_viewport.h"

#include <QVector4D>

#include <cmath>

namespace sc::app {

void MeshViewport::showView(std::optional<StandardView> view) {
  const std::span<const float> positions = pickPositions();
  std::vector<QVector3D> points(static_cast<std::size_t>(m_vertexCount));
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = QVector3D{positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
  m_camera.setViewportSize(width(), height());
  m_camera.frame(points, view);
  update();
}

void MeshViewport::setUpAxis(UpAxis axis) {
  if (axis == m_camera.upAxis()) return;
  m_camera.setUpAxis(axis);
  resetView();
}

bool MeshViewport::setPivotAt(QPointF position) {
  // The rendered surface under the cursor (the brush's depth read-back), unprojected.
  if (m_vertexCount == 0) return false;
  const DepthImage depth = renderDepth();
  const double ratio = devicePixelRatioF();
  const int column = static_cast<int>(position.x() * ratio);
  const int row = depth.height - 1 - static_cast<int>(position.y() * ratio);
  if (depth.empty() || column < 0 || row < 0 || column >= depth.width || row >= depth.height) return false;
  const float z = depth.depth[static_cast<std::size_t>(row) * static_cast<std::size_t>(depth.width) +
                              static_cast<std::size_t>(column)];
  if (!(z < 1.0f)) return false;  // the background
  const QVector4D ndc{2.0f * (static_cast<float>(column) + 0.5f) / static_cast<float>(depth.width) - 1.0f,
                      2.0f * (static_cast<float>(row) + 0.5f) / static_cast<float>(depth.height) - 1.0f,
                      2.0f * z - 1.0f, 1.0f};
  const QVector4D world = (m_camera.projection() * m_camera.view()).inverted().map(ndc);
  if (!(std::abs(world.w()) > 0.0f)) return false;
  m_camera.setPivot(world.toVector3DAffine());
  cameraMoved();
  return true;
}

}  // namespace sc::app
