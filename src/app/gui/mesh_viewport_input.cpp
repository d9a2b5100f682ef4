// MeshViewport, the mouse side: tools, brush strokes, the handle drag and the hint. The GL side is in
// mesh_viewport.cpp.

#include "app/gui/drag_gesture.h"
#include "app/gui/mesh_viewport.h"

#include <QMouseEvent>
#include <QWheelEvent>

#include <algorithm>

namespace sc::app {

namespace {

constexpr double kDepthToleranceFraction = 0.01;  // of the scene's bounding-box diagonal

}  // namespace

void MeshViewport::setTool(ViewportTool tool) {
  endGesture();
  m_tool = tool;
  update();
}

void MeshViewport::setBrushRadius(double pixels) {
  m_brushRadius = std::max(1.0, pixels);
  update();
}

void MeshViewport::setDragAllowed(bool allowed, const QString& hint) {
  m_dragAllowed = allowed;
  m_dragHint = hint;
  if (!allowed && m_gesture == Gesture::Drag) {
    endGesture();
  }
}

void MeshViewport::showHint(const QString& text) {
  m_visibleHint = text;
  m_hintTimer.start();
  update();
}

std::vector<int>& MeshViewport::brushSelection() { return m_tool == ViewportTool::HandleBrush ? m_handles : m_anchors; }

// Ends whatever gesture is in progress, emitting what its end means (the stroke's set, dragFinished()).
void MeshViewport::endGesture() {
  const Gesture gesture = m_gesture;
  m_gesture = Gesture::None;
  m_strokePoints.clear();
  m_drag.reset();
  if (gesture == Gesture::Paint) {
    if (m_tool == ViewportTool::HandleBrush) {
      emit handlePainted(m_handles);
    } else {
      emit anchorsPainted(m_anchors);
    }
  } else if (gesture == Gesture::Drag) {
    emit dragFinished();
  }
}

// === brush: project every vertex once per stroke (the camera does not move during it), then dab.
void MeshViewport::beginStroke() {
  ensureHostPositions();
  const DepthImage depth = renderDepth();
  const QSize framebuffer = (QSizeF(width(), height()) * devicePixelRatioF()).toSize();
  Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>> P(m_positions.data(), m_vertexCount, 3);
  const float diagonal = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  m_strokePoints =
      projectToScreen(m_positions, m_camera.view(), m_camera.projection(), framebuffer,
                      depth.empty() ? nullptr : &depth, static_cast<float>(kDepthToleranceFraction) * diagonal);
  m_gesture = Gesture::Paint;
}

void MeshViewport::paintDab(QPointF pos, bool erase) {
  const double ratio = devicePixelRatioF();
  const std::vector<int> hits = visibleWithin(m_strokePoints, pos * ratio, m_brushRadius * ratio);
  std::vector<int>& selection = brushSelection();
  if (hits.empty() || (erase && selection.empty())) {
    return;
  }
  selection = applyBrush(selection, hits, erase);
  rebuildTints();
  update();
}

// === drag: starts only on the mesh; returns false (the press orbits instead) when the press misses it.
bool MeshViewport::beginDrag(QPointF pos) {
  ensureHostPositions();
  const DepthImage depth = renderDepth();
  const double ratio = devicePixelRatioF();
  const int px = static_cast<int>(pos.x() * ratio);
  const int row = depth.height - 1 - static_cast<int>(pos.y() * ratio);
  if (depth.empty() || px < 0 || row < 0 || px >= depth.width || row >= depth.height ||
      depth.depth[static_cast<std::size_t>(row) * static_cast<std::size_t>(depth.width) +
                  static_cast<std::size_t>(px)] >= 1.0f) {
    return false;
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const int v : m_handles) {
    const auto i = 3 * static_cast<std::size_t>(v);
    centroid += Eigen::Vector3d(m_positions[i], m_positions[i + 1], m_positions[i + 2]);
  }
  centroid /= static_cast<double>(m_handles.size());
  m_drag =
      std::make_unique<DragGesture>(m_camera.view(), m_camera.projection(), QSizeF(width(), height()), centroid, pos);
  m_gesture = Gesture::Drag;
  emit dragStarted();
  return true;
}

void MeshViewport::mousePressEvent(QMouseEvent* event) {
  endGesture();
  const QPointF pos = event->position();
  m_lastMousePos = pos.toPoint();
  if (event->button() != Qt::LeftButton || m_tool == ViewportTool::Orbit || m_vertexCount == 0) {
    m_gesture = Gesture::Camera;
    return;
  }
  if (m_tool == ViewportTool::Drag) {
    if (!m_dragAllowed) {
      showHint(m_dragHint.isEmpty() ? tr("Dragging is not allowed now") : m_dragHint);
      m_gesture = Gesture::Blocked;
    } else if (m_handles.empty()) {
      showHint(tr("Paint a handle first"));
      m_gesture = Gesture::Blocked;
    } else if (!beginDrag(pos)) {
      m_gesture = Gesture::Camera;
    }
    return;
  }
  beginStroke();
  paintDab(pos, event->modifiers().testFlag(Qt::ShiftModifier));
}

void MeshViewport::mouseMoveEvent(QMouseEvent* event) {
  const QPointF posF = event->position();
  const QPoint pos = posF.toPoint();
  const QPoint delta = pos - m_lastMousePos;
  m_lastMousePos = pos;
  if (m_tool == ViewportTool::HandleBrush || m_tool == ViewportTool::AnchorBrush) {
    m_cursor = posF;
    update();
  }
  switch (m_gesture) {
    case Gesture::Paint:
      paintDab(posF, event->modifiers().testFlag(Qt::ShiftModifier));
      return;
    case Gesture::Drag:
      m_drag->moveTo(posF, event->modifiers().testFlag(Qt::ControlModifier));
      emit dragMoved(m_drag->translation(), m_drag->rotation());
      return;
    case Gesture::Blocked:
      return;
    case Gesture::None:
    case Gesture::Camera:
      break;
  }
  if (event->buttons() & Qt::LeftButton) {
    m_camera.orbit(static_cast<float>(delta.x()), static_cast<float>(delta.y()));
  } else if (event->buttons() & (Qt::RightButton | Qt::MiddleButton)) {
    m_camera.pan(static_cast<float>(delta.x()), static_cast<float>(delta.y()));
  } else {
    return;
  }
  markMoved();
}

void MeshViewport::mouseReleaseEvent(QMouseEvent* event) {
  if (event->buttons() == Qt::NoButton) {
    endGesture();
  }
}

void MeshViewport::mouseDoubleClickEvent(QMouseEvent* /*event*/) { resetView(); }

void MeshViewport::wheelEvent(QWheelEvent* event) {
  m_camera.zoom(static_cast<float>(event->angleDelta().y()) / 120.0f);
  markMoved();
  event->accept();
}

}  // namespace sc::app
