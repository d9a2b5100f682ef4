// MeshViewport, the data side: the mesh and its shown level (frames: LevelFrames), scene bounds, the selection with
// its vertex tints, and the view's answers to its input (ViewportInput::View). The GL side (context resources, the
// paint, depth read-back, GPU read-back) is in mesh_viewport_render.cpp.

#include "app/gui/mesh_viewport.h"

#include "app/gui/viewport/vertex_arrays.h"

#include <QMouseEvent>
#include <QVBoxLayout>

#include <algorithm>
#include <cassert>

namespace sc::app {

MeshViewport::MeshViewport(QWidget* parent)
    : QWidget(parent),
      m_frames(m_buffers, RendererDefaults::reconstructionPath()),
      m_policy(RendererDefaults::adaptiveResolution()),
      m_pictures(*this),
      m_input(*this),
      m_surface(new ViewportSurface(*this, *this)) {
  m_container = QWidget::createWindowContainer(m_surface, this);  // takes the surface
  m_container->setFocusPolicy(Qt::NoFocus);  // keys reach this widget (and the window's shortcuts) directly
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(m_container);
  setSampleCount(RendererDefaults::sampleCount());
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(true);  // the brush outline follows the cursor
  m_restoreTimer.setSingleShot(true);
  m_restoreTimer.setInterval(FramePolicy::kIdleRestoreMs +
                             FramePolicy::kIdleRestoreMs / 10);  // the next paint is no longer interactive
  connect(&m_restoreTimer, &QTimer::timeout, this, [this] { m_pictures.continuePicture(); });
  connect(m_surface, &QOpenGLWindow::frameSwapped, this, [this] {
    if (const double ms = m_policy.msSincePaint(); ms >= 0.0) {
      m_frameTimes.composeMs = ms;
    }
    emit frameSwapped();
  });
  connect(&m_input, &ViewportInput::handlePainted, this, &MeshViewport::handlePainted);
  connect(&m_input, &ViewportInput::anchorsPainted, this, &MeshViewport::anchorsPainted);
  connect(&m_input, &ViewportInput::dragStarted, this, &MeshViewport::dragStarted);
  connect(&m_input, &ViewportInput::dragMoved, this, &MeshViewport::dragMoved);
  connect(&m_input, &ViewportInput::dragFinished, this, &MeshViewport::dragFinished);
}

MeshViewport::~MeshViewport() {
  cleanup();
  delete m_container;  // the surface and its context go now, while this object is whole
}

QSize MeshViewport::minimumSizeHint() const { return {200, 150}; }

QSize MeshViewport::sizeHint() const { return {960, 720}; }

// ---------------------------------------------------------------------------------------------------- plain mesh

void MeshViewport::setMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  assert(V.cols() == 3 && F.cols() == 3 && "V and F must be #V by 3 and #F by 3");
  if (V.rows() == 0 || F.rows() == 0) {
    clearMesh();
    return;
  }
  m_input.endGesture();
  m_frames.drop();
  m_pictures.meshReplaced();
  m_origin = 0.5 * (V.colwise().minCoeff() + V.colwise().maxCoeff());
  m_vertexCount = static_cast<int>(V.rows());
  m_buffers.setIndices(flatIndices(F));
  setPositions(V);
  m_selection.clear();
  rebuildTints();
  emit meshChanged();
  resetView();
}

void MeshViewport::setPositions(const Eigen::MatrixXd& V) {
  assert(V.rows() == m_vertexCount && V.cols() == 3 && "setPositions needs the #V of the current mesh");
  if (V.rows() != m_vertexCount || V.cols() != 3 || m_vertexCount == 0) {
    return;
  }
  std::vector<float>& positions = m_buffers.writePositions();
  positions.resize(static_cast<std::size_t>(3 * V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      positions[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(V(i, k) - m_origin(k));
    }
  }
  positionsGiven();
}

void MeshViewport::setPositionsInterleaved(std::span<const float> xyz) {
  const auto n = static_cast<std::size_t>(m_vertexCount);
  assert(xyz.size() == 3 * n && "setPositionsInterleaved needs 3 floats per vertex of the current mesh");
  if (xyz.size() != 3 * n || n == 0) {
    return;
  }
  shifted(xyz, -m_origin, m_buffers.writePositions());
  positionsGiven();
}

// Explicit positions were written: they replace any shown frame; recompute the normals (the mesh's and the
// proxy's) and the scene bounds, and repaint.
void MeshViewport::positionsGiven() {
  m_frames.positionsGiven(m_frameTimes);
  updateBounds();
}

// The camera's scene bounds (LevelFrames::bounds()), timed as the frame's bounds stage; then a repaint.
void MeshViewport::updateBounds() {
  QElapsedTimer timer;
  timer.start();
  const auto [lo, hi] = m_frames.bounds();
  setSceneBounds(lo, hi, m_frames.boundsConservative());
  m_frameTimes.boundsMs = lapMs(timer);
}

void MeshViewport::setSceneBounds(const QVector3D& lo, const QVector3D& hi, bool conservative) {
  ++m_shapeVersion;
  m_camera.setSceneBounds(lo, hi);
  m_sceneDiagonal = (hi - lo).length();
  m_boundsConservative = conservative;
  markMoved();
}

void MeshViewport::clearMesh() {
  m_input.endGesture();
  m_frames.drop();
  m_pictures.meshReplaced();
  m_buffers.clear();
  m_selection.clear();
  m_vertexCount = 0;
  rebuildTints();
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
  m_buffers.setProxy(triangles.size() > 0 ? CompactProxy(triangles, m_vertexCount) : CompactProxy(),
                     flatIndices(triangles));
  if (hasReconstructionBasis() && triangles.size() > 0) {
    m_buffers.writeProxyVertices().setBasis(m_frames.shown().K(), m_buffers.rest());
  }
  m_frames.refreshProxy();
  m_buffers.gatherProxyTints();
  m_proxyShowsSelection = m_selection.shownBy(m_buffers.proxy());
  update();
}

// ---------------------------------------------------------------------------------------------------- display level

void MeshViewport::setDisplayLevel(spectral::SharedDisplayLevel level) {
  if (!level) {
    clearMesh();
    return;
  }
  const spectral::DisplayGeometry& g = level->geometry;
  const std::size_t n = level->vertexCount();
  if (n == 0 || g.indices.empty() || g.rest.size() != 3 * n || g.normals.size() != 3 * n) {
    clearMesh();
    return;
  }
  // Everything per vertex is the level's, computed with it off the GUI thread (spectral::DisplayGeometry): the
  // buffers show its arrays and the camera its box, so this costs O(#V) only for the tints (and O(m) for K).
  m_input.endGesture();
  m_frames.drop();
  m_pictures.meshReplaced();
  m_origin = g.origin;
  m_vertexCount = static_cast<int>(n);
  const spectral::QuantizedBasis& K = level->level.K;
  const bool basis = K.rows() == m_vertexCount && K.cols() > 0 && level->rest.size() == 3 * n;
  m_buffers.shareLevel(level, basis);
  m_frames.restShared(m_frameTimes);
  m_frameTimes.boundsMs = 0.0;
  setSceneBounds(QVector3D(g.lo.x(), g.lo.y(), g.lo.z()), QVector3D(g.hi.x(), g.hi.y(), g.hi.z()), false);
  m_selection.clear();
  rebuildTints();
  if (basis) {
    m_frames.hold(std::move(level));
  }  // else shown as a plain mesh
  emit meshChanged();
  resetView();
}

bool MeshViewport::showFrame(const spectral::DisplayFrame& frame) {
  if (m_frames.shown().shows(frame.Z)) {
    return false;  // a still frame (the host repeats the shape about once a second): nothing to reconstruct or repaint
  }
  if (!m_frames.show(frame.Z)) {
    return false;
  }
  applyFrame();
  return true;
}

// Shows the held level's frame on the current path (LevelFrames::apply()), then the bounds and a repaint.
void MeshViewport::applyFrame() {
  m_frames.apply(proxyMayDraw(), m_frameTimes);
  updateBounds();
}

// A gesture starts (or someone reads the positions): they become current, and so do the camera's bounds when they
// were the conservative box of a lagging frame, so that the picking pass and the next paint clip nothing the user
// points at (the conservative box may be far larger than the shape: ShownLevel::bounds()).
std::span<const float> MeshViewport::pickPositions() {
  const std::span<const float> positions = m_frames.currentPositions();
  if (tightenBounds()) {
    update();
  }
  return positions;
}

bool MeshViewport::tightenBounds() {
  if (!m_boundsConservative || m_frames.boundsConservative()) {
    return false;
  }
  const auto [lo, hi] = m_frames.bounds();
  m_camera.setSceneBounds(lo, hi);
  m_boundsConservative = false;
  return true;
}

std::vector<float> MeshViewport::hostPositions() {
  std::vector<float> xyz;
  shifted(pickPositions(), m_origin, xyz);
  return xyz;
}

void MeshViewport::setReconstructionPath(ReconstructionPath path) {
  if (m_frames.setPath(path)) {
    applyFrame();
  }
}

// ---------------------------------------------------------------------------------------------------- frames

// Whether a frame of a moving shape may draw the interactive proxy (see setInteractiveProxy()).
bool MeshViewport::proxyMayDraw() const {
  return m_policy.proxyMayDraw({.singleSampled = sampleCount() <= 0,
                                .hasProxy = !m_buffers.proxyIndices().empty(),
                                .wireframe = m_wireframe,
                                .painting = m_input.painting(),
                                .showsSelection = m_proxyShowsSelection});
}

void MeshViewport::markMoved() {
  m_policy.markMoved();
  update();
}

void MeshViewport::setAdaptiveResolution(bool on) {
  m_policy.setAdaptive(on);
  update();
}

void MeshViewport::setWireframe(bool on) {
  m_wireframe = on;
  update();
}

void MeshViewport::resetView() { showView(StandardView::Home); }

// ---------------------------------------------------------------------------------------------------- selection

void MeshViewport::setSelection(std::vector<int> handles, std::vector<int> anchors) {
  m_selection.set(std::move(handles), std::move(anchors), m_vertexCount);
  selectionEdited();
}

void MeshViewport::selectionEdited() {
  rebuildTints();
  update();
}

void MeshViewport::rebuildTints() {
  m_selection.paintTints(m_buffers, m_vertexCount);
  m_proxyShowsSelection = m_selection.shownBy(m_buffers.proxy());
}

// ---------------------------------------------------------------------------------------------------- input

void MeshViewport::setTool(ViewportTool tool) { m_input.setTool(tool); }

void MeshViewport::setBrushRadius(double pixels) { m_input.setBrushRadius(pixels); }

void MeshViewport::setDragAllowed(bool allowed, const QString& hint) { m_input.setDragAllowed(allowed, hint); }

void MeshViewport::mousePressEvent(QMouseEvent* event) { m_input.press(event); }

void MeshViewport::mouseMoveEvent(QMouseEvent* event) {
  m_input.move(event);
  setPointer(event->position());
}

void MeshViewport::leaveEvent(QEvent* event) {
  setPointer(std::nullopt);
  QWidget::leaveEvent(event);
}

// ---------------------------------------------------------------------------------------------------- presence

namespace {
QVector3D asQVector(const Eigen::RowVector3d& v) {
  return {static_cast<float>(v(0)), static_cast<float>(v(1)), static_cast<float>(v(2))};
}
}  // namespace

MeshViewport::LocalView MeshViewport::localView() const {
  const QVector3D origin = asQVector(m_origin);
  LocalView local{m_camera.eye() + origin, m_camera.target() + origin, m_camera.up(), std::nullopt, std::nullopt};
  if (m_pointer) local.pointer = *m_pointer + origin;
  const std::span<const float> xyz = m_frames.lastPositions();  // O(handle): no reconstruction for presence
  QVector3D sum;
  int count = 0;
  for (const int v : handles()) {
    const auto i = static_cast<std::size_t>(v) * 3;
    if (v < 0 || i + 2 >= xyz.size()) continue;
    sum += QVector3D(xyz[i], xyz[i + 1], xyz[i + 2]);
    ++count;
  }
  if (count > 0) local.handle = sum / static_cast<float>(count) + origin;
  return local;
}

void MeshViewport::setPresenceMarkers(std::vector<PresenceMarker> markers) {
  const QVector3D origin = asQVector(m_origin);
  for (PresenceMarker& marker : markers) {
    marker.eye -= origin;
    marker.target -= origin;
    if (marker.pointer) *marker.pointer -= origin;
    if (marker.handle) *marker.handle -= origin;
  }
  if (markers == m_presence.markers()) {
    return;  // a presence heartbeat that moved nobody: no repaint
  }
  m_presence.setMarkers(std::move(markers));
  update();
}

void MeshViewport::lookFrom(const QVector3D& eye, const QVector3D& target) {
  const QVector3D origin = asQVector(m_origin);
  m_camera.lookAt(eye - origin, target - origin);
  markMoved();
}

void MeshViewport::setPointer(std::optional<QPointF> position) {
  constexpr float kPointerRadius = 12.0f;  // pixels
  m_pointer.reset();
  if (position && m_vertexCount > 0) {
    m_pointer = surfacePointUnder(m_frames.currentPositions(), m_camera.view(), m_camera.projection(), size(),
                                  *position, kPointerRadius);
  }
}

void MeshViewport::mouseReleaseEvent(QMouseEvent* event) { m_input.release(event); }

void MeshViewport::mouseDoubleClickEvent(QMouseEvent* event) {
  if (!setPivotAt(event->position())) resetView();
}

void MeshViewport::wheelEvent(QWheelEvent* event) { m_input.wheel(event); }

}  // namespace sc::app
