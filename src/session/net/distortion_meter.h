#pragma once
// Live Hausdorff distortion of one SessionClient (issue 4 item 6): feeds a DistortionProbe from the client's
// signals (every displayed frame, predicted ones included, and withdrawn predictions; every exact Keyframe), and either
// measures the ready pairs about once a second (Live: the figures go into the client's StatsReports) or keeps every
// pair for a later, offline measurement (Record: the loss experiment, so that kd-tree work never delays datagram
// processing).
//
// Live mode measures at most `maxPerTick` pairs per tick (the newest; older ones are skipped and counted) so a
// full-resolution client at a high reference rate stays cheap: ≈ 10–20 ms per pair at 23k vertices, about a second
// at a million. The measurement runs on a DistortionWorker's thread, never on the client's: a tick only takes the
// ready pairs and hands them over with the shared display level; while the worker measures or rests (it keeps at
// most a quarter of one core, distortion_worker.h) the pairs that become ready are skipped and counted, and the
// figures reach the client (setDistortion) when the batch is done.
// Lives in the client's thread; a new level resets the probe (frames of another resolution are not comparable) and
// records the current Z as displayed. Live mode skips references for which nothing was displayed yet.

#include "session/engine/distortion_probe.h"

#include <QtCore/QObject>

#include <chrono>
#include <vector>

class QTimer;

namespace sc::session {

class SessionClient;

class DistortionWorker;

class DistortionMeter final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(DistortionMeter)

 public:
  enum class Mode { Live, Record };

  /// @param client  observed; must outlive the meter (the meter is usually its child).
  DistortionMeter(SessionClient& client, Mode mode, QObject* parent = nullptr,
                  std::chrono::milliseconds period = std::chrono::milliseconds{1000}, int maxPerTick = 4);

  /// Live: every measurement finished so far. Record: empty until measureRecorded().
  [[nodiscard]] const DistortionSummary& summary() const { return m_summary; }
  /// Pairs skipped in Live mode (more ready than maxPerTick in one tick, or ready while the worker was busy).
  [[nodiscard]] std::uint64_t skipped() const { return m_skipped; }

  /// Record mode: the pairs kept so far plus every reference still pending (takeAll()); clears them.
  std::vector<DistortionPair> takeRecorded();
  /// Record mode: drops what was recorded so far (e.g. frames before the measured drag).
  void clearRecorded();

 private:
  void tick();
  void onMeasured(const std::vector<double>& percents);

  SessionClient& m_client;
  Mode m_mode;
  int m_maxPerTick;
  DistortionProbe m_probe;
  DistortionSummary m_summary;
  std::vector<DistortionPair> m_recorded;
  std::uint64_t m_skipped = 0;
  QTimer* m_timer = nullptr;
  DistortionWorker* m_worker = nullptr;  ///< Live mode's measurements (a child of this meter)
};

}  // namespace sc::session
