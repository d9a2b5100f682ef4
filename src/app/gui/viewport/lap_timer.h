#pragma once
// lapMs() and StageClock: the stage clocks of the viewport's FrameTimes.

#include <QElapsedTimer>

#include <functional>
#include <utility>

namespace sc::app {

/// Milliseconds since `timer` was (re)started; restarts it, so that consecutive calls time consecutive stages.
inline double lapMs(QElapsedTimer& timer) {
  const double ms = static_cast<double>(timer.nsecsElapsed()) * 1e-6;
  timer.start();
  return ms;
}

/// Times the GL stages of one paint. Each stage ends with an optional observer, called with the context current
/// before the stage's time is taken (e.g. shapecast-bench-viewport's glFinish(), which attributes the rasteriser's
/// work to its stage), then its lap.
class StageClock {
 public:
  void setHook(std::function<void()> hook) { m_hook = std::move(hook); }
  void start() { m_timer.start(); }
  /// Ends a stage: the observer, then the milliseconds since start() or the previous lap().
  double lap() {
    if (m_hook) {
      m_hook();
    }
    return lapMs(m_timer);
  }

 private:
  std::function<void()> m_hook;
  QElapsedTimer m_timer;
};

}  // namespace sc::app
