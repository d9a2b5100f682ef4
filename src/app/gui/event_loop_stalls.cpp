#include "app/gui/event_loop_stalls.h"

#include <QDateTime>

#include <algorithm>
#include <cstdio>

namespace sc::app {
namespace {

constexpr int kTickMs = 10;

}  // namespace

EventLoopStalls::EventLoopStalls(std::chrono::milliseconds threshold, bool print, QObject* parent)
    : QObject(parent), m_thresholdMs(static_cast<double>(threshold.count())), m_print(print) {
  m_timer.setTimerType(Qt::PreciseTimer);
  connect(&m_timer, &QTimer::timeout, this, &EventLoopStalls::tick);
  m_clock.start();
  m_lastNs = m_clock.nsecsElapsed();
  m_timer.start(kTickMs);
  if (m_print) {
    // The wall-clock origin of the "at … s" of each stall, for scripts that line stalls up with other processes'
    // steps (scripts/gui-stalls.sh).
    std::fprintf(stderr, "shapecast: watching for event-loop stalls of %.0f ms or more (from unix time %.3f)\n",
                 m_thresholdMs, static_cast<double>(QDateTime::currentMSecsSinceEpoch()) / 1000.0);
    std::fflush(stderr);
  }
}

EventLoopStalls::~EventLoopStalls() {
  if (m_print) {
    std::fprintf(stderr, "shapecast: longest event-loop gap %.0f ms over %.1f s, %d stalls of %.0f ms or more\n",
                 m_longestMs, static_cast<double>(m_clock.elapsed()) / 1000.0, m_stalls, m_thresholdMs);
  }
}

void EventLoopStalls::tick() {
  const qint64 now = m_clock.nsecsElapsed();
  const double gapMs = static_cast<double>(now - m_lastNs) / 1e6;
  m_lastNs = now;
  m_longestMs = std::max(m_longestMs, gapMs);
  if (gapMs < m_thresholdMs) return;
  ++m_stalls;
  if (m_print) {
    std::fprintf(stderr, "shapecast: event loop stalled for %.0f ms (at %.1f s)\n", gapMs,
                 static_cast<double>(now) / 1e9);
    std::fflush(stderr);
  }
  emit stalled(gapMs);
}

}  // namespace sc::app
