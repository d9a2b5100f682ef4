#include "app/gui/viewport/viewport_input.h"

#include "app/gui/drag_gesture.h"

#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>

#include <algorithm>

namespace sc::app {

namespace {

constexpr double kDepthToleranceFraction = 0.01;  // of the scene's bounding-box diagonal

}  // namespace

ViewportInput::ViewportInput(View& view, QObject* parent) : QObject(parent), m_view(view) {
  m_hintTimer.setSingleShot(true);
  m_hintTimer.setInterval(kHintMilliseconds);
  connect(&m_hintTimer, &QTimer::timeout, this, [this] {
    m_visibleHint.clear();
    m_view.requestRepaint();
  });
}

ViewportInput::~ViewportInput() = default;

void ViewportInput::setTool(ViewportTool tool) {
  endGesture();
  m_tool = tool;
  m_view.requestRepaint();
}

void ViewportInput::setBrushRadius(double pixels) {
  m_brushRadius = std::max(1.0, pixels);
  m_view.requestRepaint();
}

void ViewportInput::setDragAllowed(bool allowed, const QString& hint) {
  m_dragAllowed = allowed;
  m_dragHint = hint;
  if (!allowed && m_gesture == Gesture::Drag) {
    endGesture();
  }
}

void ViewportInput::showHint(const QString& text) {
  m_visibleHint = text;
  m_hintTimer.start();
  m_view.requestRepaint();
}

void ViewportInput::endGesture() {
  const Gesture gesture = m_gesture;
  m_gesture = Gesture::None;
  m_strokePoints.clear();
  m_drag.reset();
  if (gesture == Gesture::Paint) {
    const bool handles = m_tool == ViewportTool::HandleBrush;
    const std::vector<int>& selection = m_view.selection(handles);
    if (handles) {
      emit handlePainted(selection);
    } else {
      emit anchorsPainted(selection);
    }
  } else if (gesture == Gesture::Drag) {
    emit dragFinished();
  }
}

// === brush: project every vertex at the start of a stroke and again whenever the shape moved since (someone else's
// drag: the camera does not move during a stroke, but the shape may), then dab.
void ViewportInput::beginStroke() {
  projectStroke();
  m_gesture = Gesture::Paint;
}

void ViewportInput::projectStroke() {
  m_strokeShape = m_view.shapeVersion();
  const std::span<const float> positions = m_view.pickPositions();
  const DepthImage depth = m_view.renderDepth();
  const QSize framebuffer = (QSizeF(m_view.viewSize()) * m_view.pixelRatio()).toSize();
  Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>> P(
      positions.data(), static_cast<Eigen::Index>(positions.size() / 3), 3);
  const float diagonal = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  const OrbitCamera& camera = m_view.viewCamera();
  m_strokePoints =
      projectToScreen(positions, camera.view(), camera.projection(), framebuffer, depth.empty() ? nullptr : &depth,
                      static_cast<float>(kDepthToleranceFraction) * diagonal);
}

void ViewportInput::paintDab(QPointF pos, bool erase) {
  if (m_view.shapeVersion() != m_strokeShape) {
    projectStroke();  // the tint must land where the brush is on the shape drawn now
  }
  const double ratio = m_view.pixelRatio();
  const std::vector<int> hits = visibleWithin(m_strokePoints, pos * ratio, m_brushRadius * ratio);
  std::vector<int>& selection = m_view.selection(m_tool == ViewportTool::HandleBrush);
  if (hits.empty() || (erase && selection.empty())) {
    return;
  }
  selection = applyBrush(selection, hits, erase);
  m_view.selectionEdited();
}

// === drag: starts only on the mesh; returns false (the press orbits instead) when the press misses it.
bool ViewportInput::beginDrag(QPointF pos) {
  const std::span<const float> positions = m_view.pickPositions();
  const DepthImage depth = m_view.renderDepth();
  const double ratio = m_view.pixelRatio();
  const int px = static_cast<int>(pos.x() * ratio);
  const int row = depth.height - 1 - static_cast<int>(pos.y() * ratio);
  if (depth.empty() || px < 0 || row < 0 || px >= depth.width || row >= depth.height ||
      depth.depth[static_cast<std::size_t>(row) * static_cast<std::size_t>(depth.width) +
                  static_cast<std::size_t>(px)] >= 1.0f) {
    return false;
  }
  const std::vector<int>& handles = m_view.selection(true);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const int v : handles) {
    const auto i = 3 * static_cast<std::size_t>(v);
    centroid += Eigen::Vector3d(positions[i], positions[i + 1], positions[i + 2]);
  }
  centroid /= static_cast<double>(handles.size());
  const OrbitCamera& camera = m_view.viewCamera();
  m_drag = std::make_unique<DragGesture>(camera.view(), camera.projection(), QSizeF(m_view.viewSize()), centroid, pos);
  m_gesture = Gesture::Drag;
  emit dragStarted();
  return true;
}

void ViewportInput::press(QMouseEvent* event) {
  endGesture();
  const QPointF pos = event->position();
  m_lastMousePos = pos.toPoint();
  // Alt+left orbits in every tool (the painting and dragging tools keep the camera at hand).
  if (event->button() != Qt::LeftButton || m_tool == ViewportTool::Orbit || m_view.vertexCount() == 0 ||
      event->modifiers().testFlag(Qt::AltModifier)) {
    m_gesture = Gesture::Camera;
    return;
  }
  if (m_tool == ViewportTool::Drag) {
    if (!m_dragAllowed) {
      showHint(m_dragHint.isEmpty() ? tr("Dragging is not allowed now") : m_dragHint);
      m_gesture = Gesture::Blocked;
    } else if (m_view.selection(true).empty()) {
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

void ViewportInput::move(QMouseEvent* event) {
  const QPointF posF = event->position();
  const QPoint pos = posF.toPoint();
  const QPoint delta = pos - m_lastMousePos;
  m_lastMousePos = pos;
  if (brushTool()) {
    m_cursor = posF;
    m_view.requestRepaint();
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
    m_view.viewCamera().orbit(static_cast<float>(delta.x()), static_cast<float>(delta.y()));
  } else if (event->buttons() & (Qt::RightButton | Qt::MiddleButton)) {
    m_view.viewCamera().pan(static_cast<float>(delta.x()), static_cast<float>(delta.y()));
  } else {
    return;
  }
  m_view.cameraMoved();
}

void ViewportInput::release(QMouseEvent* event) {
  if (event->buttons() == Qt::NoButton) {
    endGesture();
  }
}

void ViewportInput::wheel(QWheelEvent* event) {
  m_view.viewCamera().zoom(static_cast<float>(event->angleDelta().y()) / 120.0f);
  m_view.cameraMoved();
  event->accept();
}

void ViewportInput::paintOverlay(QPainter& painter, QSize size) {
  const bool brush = brushTool() && m_cursor.has_value();
  if (!brush && m_visibleHint.isEmpty()) {
    return;
  }
  painter.save();
  painter.setRenderHint(QPainter::Antialiasing);
  if (brush) {
    const QColor color = m_tool == ViewportTool::HandleBrush ? QColor(255, 110, 60) : QColor(90, 150, 255);
    painter.setPen(QPen(color, 1.5));
    painter.setBrush(Qt::NoBrush);
    painter.drawEllipse(*m_cursor, m_brushRadius, m_brushRadius);
  }
  if (!m_visibleHint.isEmpty()) {
    QFont font = painter.font();
    font.setPointSizeF(font.pointSizeF() * 1.2);
    painter.setFont(font);
    const QRect text = painter.fontMetrics().boundingRect(m_visibleHint).adjusted(-12, -7, 12, 7);
    const QRect box(QPoint((size.width() - text.width()) / 2, size.height() - text.height() - 16), text.size());
    painter.setPen(Qt::NoPen);
    painter.setBrush(QColor(20, 20, 24, 200));
    painter.drawRoundedRect(box, 6, 6);
    painter.setPen(QColor(245, 245, 245));
    painter.drawText(box, Qt::AlignCenter, m_visibleHint);
  }
  painter.restore();
}

}  // namespace sc::app
