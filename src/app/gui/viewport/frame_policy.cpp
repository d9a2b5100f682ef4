#include "app/gui/viewport/frame_policy.h"

namespace sc::app {

void FramePolicy::setAdaptive(bool on) {
  m_adaptive = on;
  m_resolution.reset();
  m_proxyResolution.reset();
}

void FramePolicy::setPaintBudget(double ms) {
  m_resolution = AdaptiveResolution(ms);
  m_proxyResolution = AdaptiveResolution(ms);
}

FramePolicy::Frame FramePolicy::begin(bool scalable, bool proxyMayDraw) {
  Frame frame;
  frame.interactive = m_sinceLastPaint.isValid() && m_sinceLastPaint.elapsed() < kIdleRestoreMs;
  frame.scalable = scalable;
  frame.moved = m_moved;
  frame.proxy = frame.interactive && scalable && m_moved && proxyMayDraw;
  frame.scale = frame.interactive && scalable ? resolutionFor(frame.proxy).scale() : 1.0;
  m_moved = false;
  return frame;
}

FramePolicy::Frame FramePolicy::standIn(bool scalable) const {
  Frame frame;
  frame.interactive = true;
  frame.scalable = scalable;
  frame.proxy = true;
  frame.scale = scalable ? m_proxyResolution.scale() : 1.0;
  return frame;
}

bool FramePolicy::end(const Frame& frame, double paintMs) {
  if (frame.scalable) {
    resolutionFor(frame.proxy).record(frame.scale, paintMs);
  }
  return frame.scale < 1.0 || frame.proxy;
}

}  // namespace sc::app
