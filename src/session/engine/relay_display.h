#pragma once
// What a relay viewer displays, and how far that was from the exact shape (issue 18 item 2; docs/protocol.md "Relay
// through NATS"). Pure: the frames the RelayReceiver applied, the exact references and the time are passed in (no
// clock, no timer, no socket); net/relay_viewer.h drives it with a timer.
//
// Concealment, as on UDP (frame_assembler.h, Concealment):
//   - HoldLast (and ZeroFill, which only concerns rows a UDP frame did not deliver: a relayed frame carries every
//     row): the newest applied frame stays on screen until a newer one arrives; a missed frame shows the previous.
//   - Extrapolate: a FramePredictor (frame_predictor.h) observes each applied frame as a whole and, while the shape
//     moves and no newer frame came, predicts the overdue frames (linear dead reckoning, at most maxFrames ahead),
//     then withdraws the prediction (shows the received frame again) one interval later. A newer frame always
//     replaces a prediction (latest wins). The predicted frames are counted (concealed frames).
// Distortion, as on UDP (distortion_probe.h): every change of the display is recorded in a DistortionProbe; an exact
// reference (the host's signed keyframe, read back by the adapter) is paired with what was displayed for its frame
// once the viewer RECEIVED that frame or a newer one (a relayed frame is whole and exact, so the entry of a received
// frame cannot change any more; a predicted one is replaced when its frame arrives). A frame the viewer got shows
// distortion 0; a frame it missed shows the held (or predicted) shape against the exact one. measure() reconstructs
// both at the viewer's level (X̂' + K·Z, the same quantised K: what remains is the missed or mispredicted motion)
// and keeps a running summary.
// Memory: O(history · m) (512 frames by default). Cost: applied() O(m); measure() ≈ 10–20 ms per pair at 23k
// vertices (two reconstructions and kd-trees; meant for a reference about once a second). Not thread-safe.

#include "session/engine/distortion_probe.h"
#include "session/engine/frame_assembler.h"
#include "session/engine/frame_predictor.h"
#include "session/engine/recent_window.h"
#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace sc::session {

/// What the display counted.
struct RelayDisplayCounts {
  std::uint64_t predicted = 0;   ///< whole frames predicted (Extrapolate): concealed frames
  std::uint64_t withdrawn = 0;   ///< predictions taken back
  std::uint64_t references = 0;  ///< exact references taken (newer than the previous one)
  std::uint64_t expired = 0;     ///< references that could not be paired (older than the kept history)
  std::uint64_t skipped = 0;     ///< ready pairs not measured (more than maxPairs at once; the newest are measured)
};

/// One measurement: the reference's frame, the frame whose display stood for it, and the distortion.
struct RelayDistortionSample {
  std::uint32_t frame = 0;
  std::uint32_t shownFrame = 0;  ///< == frame when the viewer received it (or predicted it)
  double percent = 0;            ///< Hausdorff distance, % of the rest bounding-box diagonal
};

class RelayDisplay {
 public:
  /// @param[in] concealment  Extrapolate: dead reckoning of overdue frames; any other: hold-last.
  explicit RelayDisplay(Concealment concealment = Concealment::HoldLast, PredictorSettings predictor = {},
                        std::size_t history = DistortionProbe::kDefaultHistory);
  ~RelayDisplay();
  RelayDisplay(const RelayDisplay&) = delete;
  RelayDisplay& operator=(const RelayDisplay&) = delete;

  [[nodiscard]] Concealment concealment() const { return m_concealment; }

  /// The receiver applied `frame` with the exact `Z` (m by 3) at `now`. An older frame than the received one is
  /// ignored (the receiver never applies one). The first frame fixes m; a Z of another row count is ignored.
  void applied(std::uint32_t frame, const Eigen::MatrixXd& Z, Micros now);
  /// When advance() has something to do (a predicted frame, or its withdrawal); nullopt with hold-last.
  [[nodiscard]] std::optional<Micros> nextDue() const;
  /// Applies what is due at `now` (Extrapolate); Step::None with hold-last.
  FramePredictor::Step advance(Micros now);

  [[nodiscard]] bool hasFrame() const { return m_hasFrame; }
  /// m by 3, what to show (empty before the first frame).
  [[nodiscard]] const Eigen::MatrixXd& display() const;
  /// The frame display() stands for (> receivedFrame() while a prediction is shown).
  [[nodiscard]] std::uint32_t displayedFrame() const;
  [[nodiscard]] std::uint32_t receivedFrame() const { return m_received; }

  /// An exact reference of `frame` (m by 3). Ignored unless newer than the previous reference (the keyframe is
  /// read again and again; one reference per stored keyframe).
  void reference(std::uint32_t frame, const Eigen::MatrixXd& Zexact);
  /// The pairs whose frame was received (or overtaken), oldest first; the probe forgets them.
  std::vector<DistortionPair> takeReady();
  /// Measures at most `maxPairs` (≥ 1; the newest) of takeReady()'s pairs at `level` and adds them to the summary;
  /// pairs without a displayed frame before them (just joined) or of another m than the level's are skipped
  /// silently. `diagonal`: spectral::boundingBoxDiagonal(level.restV).
  std::vector<RelayDistortionSample> measure(const spectral::ResolutionLevel& level, double diagonal, int maxPairs = 4);
  [[nodiscard]] const DistortionSummary& distortion() const { return m_summary; }
  [[nodiscard]] RelayDisplayCounts counts() const;

 private:
  void record();

  Concealment m_concealment;
  std::unique_ptr<FramePredictor> m_predictor;  ///< Extrapolate only, created by the first frame (m)
  PredictorSettings m_settings;
  DistortionProbe m_probe;
  DistortionSummary m_summary;
  Eigen::MatrixXd m_Z;  ///< the newest applied frame (hold-last's display)
  bool m_hasFrame = false;
  std::uint32_t m_received = 0;
  bool m_hasReference = false;
  std::uint32_t m_lastReference = 0;
  RelayDisplayCounts m_counts;
};

}  // namespace sc::session
