#pragma once
// EventLoopStalls: how long the GUI thread's event loop goes without turning. A coarse 10 ms timer on the thread
// notes each gap between its ticks; a gap of at least `threshold` is a stall (the window neither repainted nor
// reacted for that long). shapecast enables it with SHAPECAST_STALL_MS=N in the environment (main.cpp): each stall of
// at least N ms is printed on stderr when it ends ("shapecast: event loop stalled for 1234 ms"), and the longest gap at
// exit; it first says the wall-clock time its "at … s" counts from. scripts/large-mesh-e2e.sh and
// scripts/gui-stalls.sh read them while a client joins a million-vertex mesh. Cost: one timer tick per
// 10 ms on the thread that creates it.

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

#include <chrono>

namespace sc::app {

class EventLoopStalls final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(EventLoopStalls)

 public:
  /// Starts watching the calling thread's event loop; `print`: say each stall and the summary on stderr.
  explicit EventLoopStalls(std::chrono::milliseconds threshold, bool print = false, QObject* parent = nullptr);
  /// Prints the summary when `print`.
  ~EventLoopStalls() override;

  /// The longest gap between two turns seen so far, ms (stalls or not).
  [[nodiscard]] double longestMs() const { return m_longestMs; }
  /// Stalls seen so far (gaps ≥ threshold).
  [[nodiscard]] int stalls() const { return m_stalls; }

 signals:
  /// A gap of `ms` ≥ threshold just ended.
  void stalled(double ms);

 private:
  void tick();

  QTimer m_timer;
  QElapsedTimer m_clock;
  qint64 m_lastNs = 0;
  double m_thresholdMs;
  bool m_print;
  double m_longestMs = 0.0;
  int m_stalls = 0;
};

}  // namespace sc::app
