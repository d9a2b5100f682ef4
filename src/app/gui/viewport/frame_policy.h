#pragma once
// FramePolicy: how MeshViewport lightens the frames of a moving shape on a software rasteriser. A paint soon after
// the previous one is interactive: it may be drawn at a reduced internal resolution (AdaptiveResolution, tracked
// separately for frames of the mesh and of its interactive proxy) and, when the shape or the camera moved, as the
// interactive proxy; once idle the view is redrawn at full resolution. Pure rules over a clock; no GL, no widget.

#include "app/gui/viewport/adaptive_resolution.h"

#include <QElapsedTimer>

namespace sc::app {

class FramePolicy {
 public:
  /// Paint time (upload, background and mesh passes, resolve) that adaptive resolution keeps frames within, ms.
  static constexpr double kPaintBudgetMs = 18.0;
  /// A paint less than this long after the previous one is interactive; one this long after it, or the repaint
  /// that follows this long without paints, is drawn at full resolution.
  static constexpr int kIdleRestoreMs = 300;

  /// What the widget knows about whether a frame of a moving shape may draw the proxy.
  struct ProxyConditions {
    bool singleSampled = false;   ///< the widget's framebuffer has no multisampling
    bool hasProxy = false;        ///< a proxy is set
    bool wireframe = false;       ///< edges are drawn (the proxy would show its own)
    bool painting = false;        ///< a brush stroke is in progress
    bool showsSelection = false;  ///< the proxy keeps a vertex of each non-empty selection group
  };

  /// One paint's decision.
  struct Frame {
    bool interactive = false;  ///< soon after the previous paint
    bool scalable = false;     ///< adaptive, single-sampled and able to blit: its paint time is measured
    bool moved = false;        ///< the positions or the camera changed since the previous paint
    bool proxy = false;        ///< the mesh pass draws the interactive proxy
    double scale = 1.0;        ///< internal resolution (fraction of the widget's pixels per axis)
  };

  explicit FramePolicy(bool adaptive) : m_adaptive(adaptive) {}

  /// Adaptive resolution on or off; both scales start again from full resolution.
  void setAdaptive(bool on);
  [[nodiscard]] bool adaptive() const { return m_adaptive; }
  /// Replaces kPaintBudgetMs (ms > 0) and starts again from full resolution.
  void setPaintBudget(double ms);

  /// The positions or the camera changed since the previous paint.
  void markMoved() { m_moved = true; }
  /// Whether a frame of a moving shape may draw the proxy now: adaptive and every condition met.
  [[nodiscard]] bool proxyMayDraw(const ProxyConditions& c) const {
    return m_adaptive && c.singleSampled && c.hasProxy && !c.wireframe && !c.painting && c.showsSelection;
  }

  /// Decides the paint that starts now (and forgets the movement). `scalable`: adaptive frames can be measured and
  /// blitted here; `proxyMayDraw`: proxyMayDraw() of the current conditions.
  Frame begin(bool scalable, bool proxyMayDraw);
  /// The proxy frame that stands in for a full picture still being drawn (MeshViewport's ProgressivePicture): as an
  /// interactive frame of the moving proxy, at the proxy's current scale. `scalable`: as for begin().
  [[nodiscard]] Frame standIn(bool scalable) const;
  /// Records the measured paint time of `frame` (scalable frames only). Returns whether the view must repaint
  /// itself once idle (the frame was reduced or drew the proxy).
  bool end(const Frame& frame, double paintMs);
  /// The paint is over (after its overlay): starts the interactive window of the next one.
  void painted() { m_sinceLastPaint.start(); }
  /// Milliseconds since the end of the latest paint (negative before the first), e.g. its composition and swap.
  [[nodiscard]] double msSincePaint() const {
    return m_sinceLastPaint.isValid() ? static_cast<double>(m_sinceLastPaint.nsecsElapsed()) * 1e-6 : -1.0;
  }

 private:
  AdaptiveResolution& resolutionFor(bool proxy) { return proxy ? m_proxyResolution : m_resolution; }

  bool m_adaptive;
  bool m_moved = false;
  AdaptiveResolution m_resolution{kPaintBudgetMs};       // frames of the full mesh
  AdaptiveResolution m_proxyResolution{kPaintBudgetMs};  // frames of the interactive proxy
  QElapsedTimer m_sinceLastPaint;
};

}  // namespace sc::app
