#pragma once
// When the host sends its "still" frame (docs/protocol.md, "Still frame"): the host sends coefficient frames only
// while something moves, so when a drag pauses or ends, a client that extrapolates (Concealment::Extrapolate) would
// predict past the last frame. One frame interval after the last moving frame, with no frame since, the host
// therefore sends ONE still frame: the same Z under a new frame number (an ordinary frame on the wire). A client's
// FramePredictor then sees zero velocity and predicts nothing. Pure: the send times are passed in (no clock, no
// timer); HostEngine drives it (its nextWakeUp() includes the still frame's due time).
//
// Interval T: exponential average (weight 1/8) of the spacing of consecutive moving frames, over samples within
// [kMinSample, kMaxSample] (pauses and bursts are ignored). The still frame is due kDelayFactor · T after the last
// moving frame, clamped to [kMinDelay, kMaxDelay] (kMaxDelay before a first sample). kDelayFactor > 1 keeps a
// slightly late drag frame from triggering a still frame in mid-drag; < FramePredictor's overdue factor (1.5) so
// that the still frame normally arrives before a client starts predicting whole frames.
// Memory and cost O(1). Not thread-safe.

#include "session/engine/receiver_statistics.h"

#include <optional>

namespace sc::session {

class StillFrameSchedule {
 public:
  static constexpr Micros kMinDelay{20'000};    ///< the still frame never comes sooner after a moving frame
  static constexpr Micros kMaxDelay{100'000};   ///< nor later
  static constexpr Micros kMinSample{2'000};    ///< spacing samples below this are ignored (bursts)
  static constexpr Micros kMaxSample{250'000};  ///< and above this (pauses)
  static constexpr double kDelayFactor = 1.25;  ///< the still frame is due this many intervals after the last move

  /// Takes in a frame sent at `at`; `moved`: its Z differs from the previous frame's (a solved drag pose). Returns
  /// when the still frame is due (a moving frame), or nullopt (a frame that did not move, the still frame itself
  /// included: nothing more is scheduled until the next moving frame). Cost: O(1).
  std::optional<Micros> onFrame(Micros at, bool moved);

  /// The measured interval of moving frames; 0 before a first sample.
  Micros interval() const { return m_interval; }
  /// How long after a moving frame the still frame is due: kDelayFactor · interval(), clamped.
  Micros delay() const;

 private:
  bool m_lastMoved = false;
  Micros m_lastMovedAt{0};
  Micros m_interval{0};
};

}  // namespace sc::session
