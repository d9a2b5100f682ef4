#pragma once
// Dead reckoning of the coefficient stream (Concealment::Extrapolate, "hold-last + extrapolation"): what a client
// displays when a frame's rows, or whole frames, did not arrive. Pure: the FrameAssembler's state and the time
// are passed in (injected time, no clock, no timer, no socket); ClientDatagramChannel drives it with a timer.
//
// Model: per row r of Z, the last two values received (value z1 in frame f1, z0 in an older frame f0) give a
// velocity per frame number v = (z1 − z0) / (f1 − f0) (0 when f1 − f0 > kMaxVelocityGap or with one value only).
// The row's prediction for frame f is z1 + gain · min(f − f1, maxFrames) · v: linear dead reckoning, bounded to
// maxFrames frames ahead of the row's last value and then held. A spectral deformation is linear in the handle
// positions, so for a handle moving at constant velocity this is exact; at a turning point it overshoots.
//
// Two uses:
//   - rows a received frame did not deliver (one of its datagrams lost): display() shows the received rows as they
//     are and the others predicted for the current frame (instead of held);
//   - whole frames lost: after a frame k started at time t_k, while the stream moves (some row has v ≠ 0) and no
//     datagram of a newer frame came, frame k + j is "due" at t_k + (overdueFactor + j − 1) · T, T the measured
//     inter-frame interval; advance(now) then predicts frame k + j for j = 1..maxFrames. One interval later still
//     without a datagram it withdraws the prediction (shows frame k again): the stream has most likely stopped (a
//     host sends frames only while something moves), and a held overshoot would stay on screen until the next
//     frame. A datagram of a newer frame always replaces a prediction (latest wins).
// Still frames: when every row received in the current frame equals the row's previous value (the host's still
// frame after a drag stopped, or an idle refresh: the same Z under a new frame number), the stream has stopped.
// Z is linear in the handle poses, so no row moves then: rows the frame did not deliver are held (not predicted)
// and no whole frame is predicted until a frame that moves. If the still frame is lost altogether, the overdue
// schedule above applies: predicted frames k+1..k+maxFrames, withdrawn (overdueFactor + maxFrames) · T after
// frame k arrived.
// T: exponential average (weight 1/8) of (arrival of a frame − arrival of the previous frame) / (frame-number
// difference), over samples within [kMinInterval, kMaxInterval] (idle refreshes and pauses are ignored); no
// prediction of whole frames until a first sample exists.
// Memory O(m); cost O(m) per call that changes the display. Not thread-safe.

#include "session/engine/frame_assembler.h"
#include "session/engine/receiver_statistics.h"

#include <Eigen/Core>

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

namespace sc::session {

struct PredictorSettings {
  int maxFrames = 4;           ///< at most this many frames of prediction past a row's last value, ≥ 1
  double gain = 1.0;           ///< s in Z_k + s·(Z_k − Z_{k−1}); in (0, 1]: 1 = undamped
  double overdueFactor = 1.5;  ///< a frame is overdue this many intervals after the previous frame started, ≥ 1
};

class FramePredictor {
 public:
  static constexpr Micros kMinInterval{5'000};    ///< interval samples below this are ignored (bursts)
  static constexpr Micros kMaxInterval{250'000};  ///< and above this (pauses, idle refresh)
  static constexpr int kMaxVelocityGap = 8;       ///< frames between a row's last two values for a velocity

  /// What advance() changed.
  enum class Step {
    None,       ///< nothing due
    Predicted,  ///< display() now shows the prediction for frame displayedFrame() > receivedFrame()
    Withdrawn,  ///< the prediction was taken back: display() shows the received frame again
  };

  /// @param[in] m  rows of Z, ≥ 1.
  explicit FramePredictor(int m, PredictorSettings settings = {});

  /// Takes in the assembler's state after it applied a datagram (or a seed) at `now`: rows whose frame is newer
  /// than the row's last value shift the row's history; a new frame number resets the overdue schedule and adds
  /// an interval sample. display() then shows the current frame (rows not received in it predicted).
  /// Cost: O(m).
  void observe(const FrameAssembler& assembler, Micros now);
  /// The same for a whole frame (every row received in `frame`: the relay's exact frames, relay_display.h).
  /// \pre Z is m by 3 (a Z of another shape is ignored). Cost: O(m).
  void observeFrame(std::uint32_t frame, const Eigen::MatrixXd& Z, Micros now);

  /// When the next predicted frame (or the withdrawal) is due; nullopt when nothing is scheduled (not moving, no
  /// interval yet, before any frame, or after a withdrawal until the next frame).
  std::optional<Micros> nextDue() const;

  /// Applies what is due at `now` (when several predicted frames are overdue at once, it jumps to the newest).
  /// Cost: O(m) when it changes the display, O(1) otherwise.
  Step advance(Micros now);

  /// m by 3, what to display (zeros before any observe()).
  const Eigen::MatrixXd& display() const { return m_display; }
  /// Frame number display() stands for: receivedFrame() + predictedFrames().
  std::uint32_t displayedFrame() const { return m_received + static_cast<std::uint32_t>(m_predicted); }
  std::uint32_t receivedFrame() const { return m_received; }
  /// Whole frames predicted past the received frame (0..maxFrames).
  int predictedFrames() const { return m_predicted; }
  /// True when some row has a non-zero velocity and the current frame is not a still frame (see above).
  bool moving() const;
  /// True when every row received in the current frame is unchanged from its previous value (see above).
  bool still() const { return m_still; }
  /// The measured inter-frame interval; 0 before a first sample.
  Micros interval() const { return m_interval; }
  /// Counters: whole frames predicted, and withdrawals.
  std::uint64_t framesPredicted() const { return m_framesPredicted; }
  std::uint64_t withdrawals() const { return m_withdrawals; }

  /// The row's prediction for `frame` (row history only). Cost: O(1).
  Eigen::RowVector3d predictRow(int row, std::uint32_t frame) const;

 private:
  struct Row {
    bool seen = false;
    bool hasPrevious = false;
    std::uint32_t frame = 0;                                        ///< f1
    std::uint32_t previousFrame = 0;                                ///< f0
    Eigen::RowVector3d value = Eigen::RowVector3d::Zero();          ///< z1
    Eigen::RowVector3d previousValue = Eigen::RowVector3d::Zero();  ///< z0
  };
  void showFrame(std::uint32_t frame);
  /// Row r received value `value` in `frame`: shifts the row's history when `frame` is newer.
  void observeRow(int r, std::uint32_t frame, const Eigen::RowVector3d& value);
  /// The current frame is now `frame` (received at `now`): interval sample, schedule reset, display.
  void observeCurrent(std::uint32_t frame, Micros now);
  /// Every row received in the current frame unchanged (and at least one received). Cost: O(m).
  bool currentFrameStill() const;

  PredictorSettings m_settings;
  std::vector<Row> m_rows;
  Eigen::MatrixXd m_display;
  bool m_hasFrame = false;
  std::uint32_t m_received = 0;  ///< the assembler's current frame
  Micros m_receivedAt{0};        ///< arrival of its first datagram
  int m_predicted = 0;
  bool m_withdrawn = false;  ///< nothing more scheduled until the next frame
  bool m_still = false;      ///< currentFrameStill(), as of the last observe()
  Micros m_interval{0};
  std::uint64_t m_framesPredicted = 0;
  std::uint64_t m_withdrawals = 0;
};

}  // namespace sc::session
