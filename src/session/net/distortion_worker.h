#pragma once
// DistortionWorker: measures the live distortion pairs of a DistortionMeter (session/engine/distortion_probe.h) on
// a worker std::thread, one batch at a time, so that the client's thread (the desktop client's GUI thread) never
// waits for the reconstructions and kd-trees: at a million vertices one pair costs about a second of CPU, and four
// of them on the GUI thread once stood the window still for 21 s (issue 19 item 3, docs/benchmarks.md).
// A batch holds the level it measures (spectral::SharedDisplayLevel, shared and immutable), so a level installed
// meanwhile changes nothing for it; its figures come back through a queued call, as measured() on this object's
// thread.
// Duty: after a batch that took T seconds the worker rests for kRestFactor·T before it takes another (busy() stays
// true), so the meter keeps at most 1 / (1 + kRestFactor) of one core, whatever the level's size.
// The destructor waits for the batch in flight, if any: the worker checks a stop flag between pairs, so at most one
// pair is finished.

#include "session/engine/distortion_probe.h"
#include "spectral/display_level.h"
#include "spectral/resolution_level.h"

#include <Eigen/Core>
#include <QtCore/QObject>

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

namespace sc::session {

class DistortionWorker final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(DistortionWorker)

 public:
  /// One pair's figure: distortionPercent(level, shownZ, exactZ, diagonal) unless a test injects another.
  using Measure = std::function<double(const spectral::ResolutionLevel& level, const Eigen::MatrixXd& shownZ,
                                       const Eigen::MatrixXd& exactZ, double diagonal)>;
  /// The rest after a batch, as a multiple of the batch's time.
  static constexpr double kRestFactor = 3.0;

  explicit DistortionWorker(QObject* parent = nullptr, Measure measure = distortionPercent);
  /// Waits for the batch in flight (at most the pair being measured; the rest are dropped).
  ~DistortionWorker() override;

  /// Starts measuring `pairs` (each m by 3 shown and exact Z of `level`, m = level->basisSize()) against the
  /// bounding-box diagonal of the level's rest positions, on the worker thread. False, and nothing starts, when
  /// busy(), when `level` is null or when `pairs` is empty.
  bool start(spectral::SharedDisplayLevel level, std::vector<DistortionPair> pairs);
  /// A batch is in flight, or the worker rests after one.
  [[nodiscard]] bool busy() const;
  /// Whether a batch is in flight (measured() is still to come).
  [[nodiscard]] bool measuring() const { return m_measuring; }

 signals:
  /// The figures of the batch started last, percent of the diagonal in the pairs' order, on this object's thread.
  void measured(const std::vector<double>& percents);

 private:
  void finish(const std::vector<double>& percents, std::chrono::steady_clock::duration took);

  Measure m_measure;
  std::thread m_thread;
  std::atomic<bool> m_stop{false};
  bool m_measuring = false;
  std::chrono::steady_clock::time_point m_restUntil{};
};

}  // namespace sc::session
