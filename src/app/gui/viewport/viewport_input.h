#pragma once
// ViewportInput: MeshViewport's mouse side. Tools, camera gestures (orbit, pan, zoom), brush strokes over the
// visible vertices, the handle drag (DragGesture) and the hint shown when a drag is refused, plus their overlay
// (brush outline, hint). It turns gestures into intent signals; the widget forwards them as its own.

#include "app/gui/mesh_viewport_types.h"
#include "app/gui/orbit_camera.h"
#include "app/gui/vertex_picking.h"

#include <Eigen/Core>

#include <QObject>
#include <QPoint>
#include <QSize>
#include <QString>
#include <QTimer>

#include <memory>
#include <optional>
#include <span>
#include <vector>

class QMouseEvent;
class QPainter;
class QWheelEvent;

namespace sc::app {

class DragGesture;

class ViewportInput : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ViewportInput)

 public:
  static constexpr double kDefaultBrushRadius = 30.0;  ///< pixels.
  static constexpr int kHintMilliseconds = 2000;       ///< how long a drag hint stays on screen.

  /// What the input needs of its view (MeshViewport implements it).
  class View {
   public:
    /// The view's size in logical pixels and its device pixel ratio.
    [[nodiscard]] virtual QSize viewSize() const = 0;
    [[nodiscard]] virtual double pixelRatio() const = 0;
    /// Schedules a repaint (e.g. the brush outline moved).
    virtual void requestRepaint() = 0;
    [[nodiscard]] virtual OrbitCamera& viewCamera() = 0;
    [[nodiscard]] virtual int vertexCount() const = 0;
    /// 3·#V positions as drawn now (relative to the view's origin, current), for a gesture that starts.
    [[nodiscard]] virtual std::span<const float> pickPositions() = 0;
    /// The depth of the mesh as drawn now, read back (see MeshViewport's picking).
    [[nodiscard]] virtual DepthImage renderDepth() = 0;
    /// The handle (true) or anchor vertices, sorted and unique; the brush edits them, then selectionEdited().
    [[nodiscard]] virtual std::vector<int>& selection(bool handles) = 0;
    virtual void selectionEdited() = 0;
    /// The camera moved (repaint as a moving frame).
    virtual void cameraMoved() = 0;
    /// Changes whenever the drawn positions change (a frame arrived, positions were given, another mesh).
    [[nodiscard]] virtual unsigned shapeVersion() const = 0;

   protected:
    virtual ~View() = default;
  };

  explicit ViewportInput(View& view, QObject* parent = nullptr);
  ~ViewportInput() override;

  /// Chooses what a left drag does; ends a gesture in progress (a drag in progress emits dragFinished()).
  void setTool(ViewportTool tool);
  [[nodiscard]] ViewportTool tool() const { return m_tool; }
  /// Brush radius in widget (logical) pixels; clamped to ≥ 1.
  void setBrushRadius(double pixels);
  [[nodiscard]] double brushRadius() const { return m_brushRadius; }
  /// See MeshViewport::setDragAllowed().
  void setDragAllowed(bool allowed, const QString& hint);
  [[nodiscard]] bool dragAllowed() const { return m_dragAllowed; }
  [[nodiscard]] QString visibleHint() const { return m_visibleHint; }
  /// Whether a brush stroke is in progress.
  [[nodiscard]] bool painting() const { return m_gesture == Gesture::Paint; }

  /// Ends whatever gesture is in progress, emitting what its end means (the stroke's set, dragFinished()).
  void endGesture();
  /// Whether paintOverlay() draws anything (the brush outline or the hint).
  [[nodiscard]] bool overlayShown() const { return (brushTool() && m_cursor.has_value()) || !m_visibleHint.isEmpty(); }
  /// Paints the brush outline and the hint over the view of `size` logical pixels.
  void paintOverlay(QPainter& painter, QSize size);

  void press(QMouseEvent* event);
  void move(QMouseEvent* event);
  void release(QMouseEvent* event);
  void wheel(QWheelEvent* event);

 signals:
  void handlePainted(std::vector<int> handles);
  void anchorsPainted(std::vector<int> anchors);
  void dragStarted();
  void dragMoved(Eigen::Vector3d translation, Eigen::Matrix3d rotation);
  void dragFinished();

 private:
  enum class Gesture { None, Camera, Paint, Drag, Blocked };

  void beginStroke();
  /// Projects every vertex as drawn now (the stroke's screen points, with their visibility).
  void projectStroke();
  void paintDab(QPointF pos, bool erase);
  bool beginDrag(QPointF pos);
  void showHint(const QString& text);
  [[nodiscard]] bool brushTool() const {
    return m_tool == ViewportTool::HandleBrush || m_tool == ViewportTool::AnchorBrush;
  }

  View& m_view;
  ViewportTool m_tool = ViewportTool::Orbit;
  double m_brushRadius = kDefaultBrushRadius;
  bool m_dragAllowed = true;
  QString m_dragHint;
  QString m_visibleHint;
  QTimer m_hintTimer;
  Gesture m_gesture = Gesture::None;
  QPoint m_lastMousePos;
  std::optional<QPointF> m_cursor;          // for the brush outline
  std::vector<ScreenPoint> m_strokePoints;  // projected at the start of a stroke, again when the shape moved
  unsigned m_strokeShape = 0;               // the view's shapeVersion() m_strokePoints were projected at
  std::unique_ptr<DragGesture> m_drag;
};

}  // namespace sc::app
