#pragma once
// lapMs(): the stage clock of the viewport's FrameTimes.

#include <QElapsedTimer>

namespace sc::app {

/// Milliseconds since `timer` was (re)started; restarts it, so that consecutive calls time consecutive stages.
inline double lapMs(QElapsedTimer& timer) {
  const double ms = static_cast<double>(timer.nsecsElapsed()) * 1e-6;
  timer.start();
  return ms;
}

}  // namespace sc::app
