// MeshViewport, the data side: host buffers (positions, normals, indices), scene bounds, the selection with its
// vertex tints and the QPainter overlay (brush outline, drag hint). The GL side (context resources, the
// shaded/wireframe passes, depth read-back for picking) is in mesh_viewport_render.cpp, the vertex arrays and buffer
// uploads in mesh_viewport_buffers.cpp, the GPU reconstruction in mesh_viewport_gpu.cpp, the mouse side in
// mesh_viewport_input.cpp.

#include "app/gui/mesh_viewport.h"

#include "app/gui/drag_gesture.h"
#include "app/gui/vertex_normals.h"

#include <QOpenGLFramebufferObject>  // complete types for the unique_ptr members (constructor, destructor)
#include <QOpenGLShaderProgram>
#include <QPainter>

#include <algorithm>
#include <cassert>
#include <limits>

namespace sc::app {

namespace {

constexpr std::uint8_t kHandleTint[4] = {255, 72, 20, 230};   // orange-red
constexpr std::uint8_t kAnchorTint[4] = {40, 110, 255, 210};  // blue

}  // namespace

MeshViewport::MeshViewport(QWidget* parent) : QOpenGLWidget(parent) {
  setSampleCount(defaultSampleCount());
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(true);  // the brush outline follows the cursor
  m_hintTimer.setSingleShot(true);
  m_hintTimer.setInterval(kHintMilliseconds);
  connect(&m_hintTimer, &QTimer::timeout, this, [this] {
    m_visibleHint.clear();
    update();
  });
  m_adaptive = defaultAdaptiveResolution();
  m_path = defaultReconstructionPath();
  m_restoreTimer.setSingleShot(true);
  m_restoreTimer.setInterval(kIdleRestoreMs + kIdleRestoreMs / 10);  // the next paint is no longer interactive
  connect(&m_restoreTimer, &QTimer::timeout, this, qOverload<>(&MeshViewport::update));
  connect(this, &QOpenGLWidget::frameSwapped, this, [this] {
    if (m_sinceLastPaint.isValid()) {
      m_frameTimes.composeMs = static_cast<double>(m_sinceLastPaint.nsecsElapsed()) * 1e-6;
    }
  });
}

MeshViewport::~MeshViewport() { cleanup(); }

double MeshViewport::lapMs(QElapsedTimer& timer) {
  const double ms = static_cast<double>(timer.nsecsElapsed()) * 1e-6;
  timer.start();
  return ms;
}

QSize MeshViewport::minimumSizeHint() const { return {200, 150}; }

QSize MeshViewport::sizeHint() const { return {960, 720}; }

void MeshViewport::setMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  assert(V.cols() == 3 && F.cols() == 3 && "V and F must be #V by 3 and #F by 3");
  if (V.rows() == 0 || F.rows() == 0) {
    clearMesh();
    return;
  }
  endGesture();
  dropBasis();
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  const Eigen::RowVector3d hi = V.colwise().maxCoeff();
  m_origin = 0.5 * (lo + hi);
  m_vertexCount = static_cast<int>(V.rows());
  m_proxyIndices.clear();
  m_proxy = CompactProxy();
  m_indices.resize(static_cast<std::size_t>(F.size()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      m_indices[static_cast<std::size_t>(3 * f + c)] = static_cast<std::uint32_t>(F(f, c));
    }
  }
  m_indicesDirty = true;
  setPositions(V);
  m_handles.clear();
  m_anchors.clear();
  rebuildTints();
  emit meshChanged();
  resetView();
}

void MeshViewport::setPositions(const Eigen::MatrixXd& V) {
  assert(V.rows() == m_vertexCount && V.cols() == 3 && "setPositions needs the #V of the current mesh");
  if (V.rows() != m_vertexCount || V.cols() != 3 || m_vertexCount == 0) {
    return;
  }
  m_showingCoefficients = false;
  m_hostPositionsStale = false;
  m_frameTimes.reconstructMs = 0.0;
  m_positions.resize(static_cast<std::size_t>(3 * V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      m_positions[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(V(i, k) - m_origin(k));
    }
  }
  positionsChanged();
}

void MeshViewport::setPositionsInterleaved(std::span<const float> xyz) {
  const auto n = static_cast<std::size_t>(m_vertexCount);
  assert(xyz.size() == 3 * n && "setPositionsInterleaved needs 3 floats per vertex of the current mesh");
  if (xyz.size() != 3 * n || n == 0) {
    return;
  }
  m_showingCoefficients = false;
  m_hostPositionsStale = false;
  m_frameTimes.reconstructMs = 0.0;
  const float origin[3] = {static_cast<float>(m_origin(0)), static_cast<float>(m_origin(1)),
                           static_cast<float>(m_origin(2))};
  m_positions.resize(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    m_positions[i] = xyz[i] - origin[i % 3];
  }
  positionsChanged();
}

// m_positions changed: recompute the normals (the mesh's and the proxy's) and the scene bounds, mark the upload and
// repaint.
void MeshViewport::positionsChanged() {
  QElapsedTimer timer;
  timer.start();
  m_normals.resize(m_positions.size());
  vertexNormals(m_positions, m_indices, m_normals);
  m_normalsStale = false;
  refreshProxyPositions();
  m_frameTimes.normalsMs = lapMs(timer);
  updateBounds();
  m_frameTimes.boundsMs = lapMs(timer);
  m_vertexDataDirty = true;
  markMoved();
}

// The camera's scene bounds from m_positions (exact), or while they lag the coefficients (GPU path, proxy-only
// frames) from the rest bounds widened by
// max_i ‖K_i‖·‖Z_c‖ ≥ |(K·Z)_ic| per coordinate (Cauchy–Schwarz), which needs no reconstruction.
void MeshViewport::updateBounds() {
  if (m_showingCoefficients && m_hostPositionsStale) {
    const Eigen::Vector3f reach = m_basisMaxRowNorm * m_coefficients.colwise().norm().transpose();
    const Eigen::Vector3f lo = m_restLo - reach;
    const Eigen::Vector3f hi = m_restHi + reach;
    m_camera.setSceneBounds(QVector3D(lo.x(), lo.y(), lo.z()), QVector3D(hi.x(), hi.y(), hi.z()));
    return;
  }
  QVector3D lo(std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max());
  QVector3D hi = -lo;
  for (std::size_t i = 0; i < m_positions.size(); i += 3) {
    const QVector3D p(m_positions[i], m_positions[i + 1], m_positions[i + 2]);
    lo = QVector3D(std::min(lo.x(), p.x()), std::min(lo.y(), p.y()), std::min(lo.z(), p.z()));
    hi = QVector3D(std::max(hi.x(), p.x()), std::max(hi.y(), p.y()), std::max(hi.z(), p.z()));
  }
  m_camera.setSceneBounds(lo, hi);
}

void MeshViewport::clearMesh() {
  endGesture();
  dropBasis();
  m_positions.clear();
  m_normals.clear();
  m_indices.clear();
  m_proxyIndices.clear();
  m_proxy = CompactProxy();
  m_handles.clear();
  m_anchors.clear();
  m_vertexCount = 0;
  rebuildTints();
  m_vertexDataDirty = true;
  m_indicesDirty = true;
  emit meshChanged();
  update();
}

void MeshViewport::setInteractiveProxy(const Eigen::MatrixXi& triangles) {
  const bool valid = triangles.size() == 0 ||
                     (triangles.cols() == 3 && triangles.minCoeff() >= 0 && triangles.maxCoeff() < m_vertexCount);
  assert(valid && "setInteractiveProxy needs #P by 3 indices into the current mesh's vertices");
  if (!valid) {
    return;
  }
  m_proxyIndices.resize(static_cast<std::size_t>(triangles.size()));
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      m_proxyIndices[static_cast<std::size_t>(3 * f + c)] = static_cast<std::uint32_t>(triangles(f, c));
    }
  }
  m_proxy = triangles.size() > 0 ? CompactProxy(triangles, m_vertexCount) : CompactProxy();
  if (!m_proxy.empty()) {
    if (hasReconstructionBasis()) {
      m_proxy.setBasis(m_basis, m_rest);
    }
    refreshProxyPositions();
    m_proxy.gatherTints(m_tints);
  }
  m_indicesDirty = true;
  m_proxyIndicesDirty = true;
  m_proxyTintsDirty = true;
  updateProxySelection();
  update();
}

// The proxy's positions and normals for the current picture: reconstructed from its rows of K while the picture is
// rest + K·Z with the mesh's positions lagging (m_positions may be stale), else gathered from m_positions.
void MeshViewport::refreshProxyPositions() {
  if (m_proxy.empty()) {
    return;
  }
  if (m_showingCoefficients && m_hostPositionsStale && m_proxy.hasBasis()) {
    m_proxy.reconstruct(m_coefficients);
  } else {
    m_proxy.gatherPositions(m_positions);
  }
  m_proxy.updateNormals();
  m_proxyDataDirty = true;
}

void MeshViewport::updateProxySelection() {
  const auto shown = [this](const std::vector<int>& group) {
    return group.empty() || std::any_of(group.begin(), group.end(), [this](int v) { return m_proxy.uses(v); });
  };
  m_proxyShowsSelection = m_proxy.empty() || (shown(m_handles) && shown(m_anchors));
}

void MeshViewport::markMoved() {
  m_moved = true;
  update();
}

void MeshViewport::setSelection(std::vector<int> handles, std::vector<int> anchors) {
  for (std::vector<int>* set : {&handles, &anchors}) {
    std::erase_if(*set, [this](int i) { return i < 0 || i >= m_vertexCount; });
    std::sort(set->begin(), set->end());
    set->erase(std::unique(set->begin(), set->end()), set->end());
  }
  m_handles = std::move(handles);
  m_anchors = std::move(anchors);
  rebuildTints();
  update();
}

void MeshViewport::rebuildTints() {
  m_tints.assign(4 * static_cast<std::size_t>(m_vertexCount), 0);
  for (const auto& [set, tint] : {std::pair{&m_anchors, kAnchorTint}, std::pair{&m_handles, kHandleTint}}) {
    for (const int v : *set) {
      std::copy(tint, tint + 4, m_tints.begin() + 4 * static_cast<std::ptrdiff_t>(v));
    }
  }
  m_tintsDirty = true;
  if (!m_proxy.empty()) {
    m_proxy.gatherTints(m_tints);
    m_proxyTintsDirty = true;
  }
  updateProxySelection();
}

void MeshViewport::setWireframe(bool on) {
  m_wireframe = on;
  update();
}

void MeshViewport::resetView() {
  ensureHostPositions();
  std::vector<QVector3D> points(static_cast<std::size_t>(m_vertexCount));
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = QVector3D{m_positions[3 * i], m_positions[3 * i + 1], m_positions[3 * i + 2]};
  }
  m_camera.setViewportSize(width(), height());
  m_camera.frame(points);
  update();
}

// QPainter over the GL picture: the brush outline and the drag hint. Skipped (no QPainter) when neither shows.
void MeshViewport::drawOverlay() {
  const bool brush =
      (m_tool == ViewportTool::HandleBrush || m_tool == ViewportTool::AnchorBrush) && m_cursor.has_value();
  if (!brush && m_visibleHint.isEmpty()) {
    return;
  }
  QPainter painter(this);
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
    const QRect box(QPoint((width() - text.width()) / 2, height() - text.height() - 16), text.size());
    painter.setPen(Qt::NoPen);
    painter.setBrush(QColor(20, 20, 24, 200));
    painter.drawRoundedRect(box, 6, 6);
    painter.setPen(QColor(245, 245, 245));
    painter.drawText(box, Qt::AlignCenter, m_visibleHint);
  }
}

}  // namespace sc::app
