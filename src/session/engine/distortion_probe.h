#pragma once
// Distortion of what a client displayed against the exact frame (live and offline). The host sends exact
// reference frames (Keyframes, TCP) at a low rate; the client keeps the coefficients it displayed per frame and,
// once a reference's frame has had its chance (its datagrams are no longer expected), measures the vertex-set
// Hausdorff distance between the two reconstructions at its own resolution, as a percentage of the rest bounding-
// box diagonal (shared/design/spectral.md §7). Pure: no Qt objects, no clock, no sockets. Not thread-safe.

#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace sc::session {

/// One measurement to make: what was shown for `frame` and what it should have been.
struct DistortionPair {
  std::uint32_t frame = 0;       ///< the reference's frame number
  std::uint32_t shownFrame = 0;  ///< frame whose displayed Z stands for `frame` (≤ frame; == frame if it arrived)
  bool displayedAny = false;     ///< false: nothing was displayed up to `frame`, `shown` is the rest shape (Z = 0)
  Eigen::MatrixXd shown;         ///< m by 3, the last Z displayed while `shownFrame` was current
  Eigen::MatrixXd exact;         ///< m by 3, the reference (exact) Z
};

/// Contract:
///  - displayed(frame, Z) is called after every change of the displayed Z (datagram applied, seed). For each frame
///    number the probe keeps the LAST Z displayed while that frame was current, for the newest `history` frames
///    (oldest evicted first). Frame numbers compare in 32-bit serial-number arithmetic (RFC 1982), so they wrap.
///  - reference(frame, Zexact) queues an exact reference.
///  - takeReady(current) returns the pairs of the references whose frame is older than `current` (the frame now
///    displayed: a newer frame started, so the reference frame's datagrams had their chance), oldest first.
///    `shown` is the entry of the newest displayed frame ≤ the reference frame: when a whole frame was lost the
///    previous frame stayed on screen (hold-last at frame level); when nothing was displayed yet, Z = 0 (the rest
///    shape). A reference older than the evicted history cannot be matched and is discarded (expired()).
///  - takeAll() returns every queued reference's pair (end of a run: no newer frame will come).
/// Memory: O(history · m + pending references · m). Cost: displayed() O(m) amortised (copy of Z; O(history) only
/// for an out-of-order frame); takeReady() O(pending · (log history + m)).
class DistortionProbe {
 public:
  static constexpr std::size_t kDefaultHistory = 512;

  /// @param[in] history  frames of displayed Z kept, ≥ 1.
  explicit DistortionProbe(std::size_t history = kDefaultHistory);

  /// @param[in] Z  m by 3, the coefficients now displayed for `frame`.
  void displayed(std::uint32_t frame, const Eigen::MatrixXd& Z);
  /// The display went back to `frame` (a predicted frame was taken back, ClientDatagramChannel::
  /// predictionWithdrawn): the entries of frames newer than `frame` are forgotten, so that a later reference of
  /// such a frame is paired with what is displayed from now on, not with the withdrawn prediction. Cost: O(removed).
  void withdraw(std::uint32_t frame);
  /// @param[in] Zexact  m by 3, the exact coefficients of `frame` (a Keyframe).
  void reference(std::uint32_t frame, const Eigen::MatrixXd& Zexact);

  std::vector<DistortionPair> takeReady(std::uint32_t currentFrame);
  std::vector<DistortionPair> takeAll();

  /// Forgets the history and the pending references (e.g. a new resolution level or a new session).
  void reset();

  std::size_t pendingReferences() const { return m_references.size(); }
  std::size_t historySize() const { return m_history.size(); }
  /// References discarded because their frame was older than the kept history.
  std::uint64_t expired() const { return m_expired; }

 private:
  struct Entry {
    std::uint32_t frame;
    Eigen::MatrixXd Z;
  };
  bool pairFor(std::uint32_t frame, const Eigen::MatrixXd& exact, DistortionPair& out) const;

  std::size_t m_capacity;
  std::deque<Entry> m_history;  ///< ascending frame order (serial arithmetic)
  std::deque<Entry> m_references;
  bool m_evicted = false;             ///< some history was evicted: frames before the front are unknown
  std::uint32_t m_newestEvicted = 0;  ///< newest evicted frame (valid when m_evicted)
  std::uint64_t m_expired = 0;
};

/// Reconstructs X_s = X̂' + K·shownZ and X_e = X̂' + K·exactZ at `level`'s resolution (in double precision from
/// the float K) and returns their vertex-set Hausdorff distance (spectral::hausdorffDistance) as a percentage of
/// `diagonal`.
/// @param[in] level  the client's display level: restV n' by 3, K n' by m.
/// @param[in] shownZ, exactZ  m by 3 each.
/// @param[in] diagonal  the rest bounding-box diagonal, > 0. Pass spectral::boundingBoxDiagonal(level.restV): the
///            decimated rest mesh's vertices lie on (or within the decimation error of) the full surface, so its
///            diagonal equals the full mesh's within that error and percentages are comparable across levels.
/// @return percent ≥ 0; 0 when shownZ == exactZ; NaN when diagonal ≤ 0.
/// \pre shapes as stated (asserted). Cost: O(n'·m) for the two reconstructions plus O(n' log n') for the two
///      kd-trees (≈ 10–20 ms at n' = 23k); meant for reference frames at a low rate, not every frame.
double distortionPercent(const spectral::ResolutionLevel& level, const Eigen::MatrixXd& shownZ,
                         const Eigen::MatrixXd& exactZ, double diagonal);

/// Running summary of distortion measurements (percent of the diagonal). NaN samples are ignored.
struct DistortionSummary {
  double maxPct = 0.0;
  double meanPct = 0.0;
  double lastPct = 0.0;
  std::uint64_t count = 0;

  void add(double pct);
  void reset() { *this = DistortionSummary{}; }
};

}  // namespace sc::session
