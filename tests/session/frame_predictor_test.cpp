// Tests src/session/engine/frame_predictor.cpp: dead reckoning of missing rows and of overdue whole frames, with
// injected time (no sockets, no clock).
#include "session/engine/frame_predictor.h"
#include "session/wire/coefficient_codec.h"

#include <gtest/gtest.h>

#include <vector>

namespace {

using namespace sc::session;
using namespace std::chrono_literals;

const QByteArray kPredictorKey = QByteArrayLiteral("predictor-key");
constexpr std::uint16_t kPredictorPeer = 4;
constexpr int kPredictorM = 40;
constexpr Micros kT = 33'000us;  ///< inter-frame interval of the tests

/// Z of frame f on a straight line: A + f·B (a handle moving at constant velocity), one row scale per band.
Eigen::MatrixXd linearZ(double f) {
  Eigen::MatrixXd Z(kPredictorM, 3);
  for (int k = 0; k < kPredictorM; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = (0.3 * (c + 1) + 0.01 * f * (c - 1.5)) / (1.0 + k);
  return Z;
}

/// Drives one FrameAssembler and one FramePredictor from encoded frames, and keeps what a lossless receiver
/// saw per frame (the dequantised Z) to compare with.
struct Receiver {
  explicit Receiver(PredictorSettings settings = {}) : predictor(kPredictorM, settings) {}

  /// Frame f (Z) arrives at `at`; `lostPart` ≥ 0 drops that datagram of the frame.
  void receive(std::uint32_t f, const Eigen::MatrixXd& Z, Micros at, int lostPart = -1) {
    const std::vector<QByteArray> parts = encoder.encodeFrame(f, Z);
    FrameAssembler exact(kPredictorKey, kPredictorPeer, kPredictorM);
    for (const QByteArray& p : parts) EXPECT_EQ(exact.receive(p), DecodeError::None);
    views.push_back(exact.z());
    for (int j = 0; j < static_cast<int>(parts.size()); ++j) {
      if (j == lostPart) continue;
      ASSERT_EQ(assembler.receive(parts[static_cast<std::size_t>(j)]), DecodeError::None);
      predictor.observe(assembler, at);
    }
  }

  CoefficientEncoder encoder{kPredictorKey, kPredictorPeer};
  FrameAssembler assembler{kPredictorKey, kPredictorPeer, kPredictorM, Concealment::Extrapolate};
  FramePredictor predictor;
  std::vector<Eigen::MatrixXd> views;  ///< views[i]: the dequantised Z of the i-th frame sent
};

TEST(FramePredictor, ShowsTheReceivedFrameAsIs) {
  Receiver r;
  r.receive(1, linearZ(1), 0us);
  r.receive(2, linearZ(2), kT);
  EXPECT_EQ(r.predictor.display(), r.views[1]);
  EXPECT_EQ(r.predictor.displayedFrame(), 2u);
  EXPECT_EQ(r.predictor.predictedFrames(), 0);
  EXPECT_TRUE(r.predictor.moving());
  EXPECT_EQ(r.predictor.interval(), kT);
}

TEST(FramePredictor, OverdueFramesAreExtrapolatedThenWithdrawn) {
  Receiver r;  // maxFrames 4, gain 1, overdue 1.5
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  const Micros last = 2 * kT;
  const Eigen::MatrixXd velocity = r.views[2] - r.views[1];
  ASSERT_TRUE(r.predictor.nextDue().has_value());
  EXPECT_EQ(*r.predictor.nextDue(), last + kT + kT / 2);
  EXPECT_EQ(r.predictor.advance(last + kT + kT / 2 - 1us), FramePredictor::Step::None);
  for (int j = 1; j <= 4; ++j) {
    const Micros due = *r.predictor.nextDue();
    EXPECT_EQ(due, last + kT / 2 + j * kT);
    ASSERT_EQ(r.predictor.advance(due), FramePredictor::Step::Predicted);
    EXPECT_EQ(r.predictor.displayedFrame(), 3u + static_cast<std::uint32_t>(j));
    EXPECT_EQ(r.predictor.receivedFrame(), 3u);
    EXPECT_LT((r.predictor.display() - (r.views[2] + j * velocity)).cwiseAbs().maxCoeff(), 1e-12);
    // Linear motion: the prediction is the true frame within the codec's quantisation.
    EXPECT_LT((r.predictor.display() - linearZ(3 + j)).cwiseAbs().maxCoeff(), 1e-3);
  }
  ASSERT_EQ(r.predictor.advance(*r.predictor.nextDue()), FramePredictor::Step::Withdrawn);
  EXPECT_EQ(r.predictor.displayedFrame(), 3u);
  EXPECT_EQ(r.predictor.display(), r.views[2]);
  EXPECT_FALSE(r.predictor.nextDue().has_value());
  EXPECT_EQ(r.predictor.framesPredicted(), 4u);
  EXPECT_EQ(r.predictor.withdrawals(), 1u);
}

TEST(FramePredictor, ALateTimerJumpsToTheNewestDueFrame) {
  Receiver r;
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  // 3.5 intervals after frame 3: frames 4, 5 and 6 are due; the display jumps to 6.
  ASSERT_EQ(r.predictor.advance(2 * kT + 3 * kT + kT / 2), FramePredictor::Step::Predicted);
  EXPECT_EQ(r.predictor.displayedFrame(), 6u);
  EXPECT_EQ(r.predictor.framesPredicted(), 3u);
  // Far later: past maxFrames, withdrawn at once.
  EXPECT_EQ(r.predictor.advance(2 * kT + 20 * kT), FramePredictor::Step::Withdrawn);
}

TEST(FramePredictor, ARealFrameReplacesThePrediction) {
  Receiver r;
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  ASSERT_EQ(r.predictor.advance(*r.predictor.nextDue()), FramePredictor::Step::Predicted);
  ASSERT_EQ(r.predictor.displayedFrame(), 4u);
  // Frame 4 was lost; frame 5 arrives and is shown as it is, whatever was predicted.
  r.receive(5, linearZ(5) * 2.0, 4 * kT);
  EXPECT_EQ(r.predictor.displayedFrame(), 5u);
  EXPECT_EQ(r.predictor.predictedFrames(), 0);
  EXPECT_EQ(r.predictor.display(), r.views[3]);
  // The schedule restarts from frame 5's arrival.
  ASSERT_TRUE(r.predictor.nextDue().has_value());
  EXPECT_EQ(*r.predictor.nextDue(), 4 * kT + kT + kT / 2);
}

TEST(FramePredictor, RowsAFrameDidNotDeliverAreExtrapolated) {
  Receiver r;
  r.receive(1, linearZ(1), 0us);
  r.receive(2, linearZ(2), kT);
  r.receive(3, linearZ(3), 2 * kT, /*lostPart=*/1);
  int extrapolated = 0;
  for (int k = 0; k < kPredictorM; ++k) {
    const bool delivered = r.assembler.rowFrame(k) == 3u;
    const Eigen::RowVector3d expected = delivered ? Eigen::RowVector3d(r.views[2].row(k))
                                                  : Eigen::RowVector3d(2.0 * r.views[1].row(k) - r.views[0].row(k));
    extrapolated += delivered ? 0 : 1;
    EXPECT_LT((r.predictor.display().row(k) - expected).cwiseAbs().maxCoeff(), 1e-12) << "row " << k;
    // Hold-last would show views[1] in the lost rows; the extrapolation is the true frame within quantisation.
    EXPECT_LT((r.predictor.display().row(k) - linearZ(3).row(k)).cwiseAbs().maxCoeff(), 1e-3) << "row " << k;
  }
  EXPECT_GT(extrapolated, 0);
  EXPECT_EQ(r.predictor.displayedFrame(), 3u);
}

TEST(FramePredictor, AStillStreamSchedulesNothing) {
  Receiver r;
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(1), (f - 1) * kT);
  EXPECT_FALSE(r.predictor.moving());
  EXPECT_FALSE(r.predictor.nextDue().has_value());
  EXPECT_EQ(r.predictor.advance(10 * kT), FramePredictor::Step::None);
  EXPECT_EQ(r.predictor.display(), r.views[2]);
}

TEST(FramePredictor, AStillFrameAfterMotionPredictsNothing) {
  Receiver r;
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  ASSERT_TRUE(r.predictor.moving());
  // The host's still frame: frame 3's Z under frame number 4, one interval later.
  r.receive(4, linearZ(3), 3 * kT);
  EXPECT_TRUE(r.predictor.still());
  EXPECT_FALSE(r.predictor.moving());
  EXPECT_FALSE(r.predictor.nextDue().has_value());
  EXPECT_EQ(r.predictor.advance(3 * kT + 10 * kT), FramePredictor::Step::None);
  EXPECT_EQ(r.predictor.displayedFrame(), 4u);
  EXPECT_EQ(r.predictor.display(), r.views[2]);  // the last real frame's Z, exactly
  EXPECT_EQ(r.predictor.framesPredicted(), 0u);
  // The next moving frame is extrapolated again.
  r.receive(5, linearZ(5), 4 * kT);
  EXPECT_FALSE(r.predictor.still());
  EXPECT_TRUE(r.predictor.moving());
}

TEST(FramePredictor, AStillFrameMissingADatagramHoldsEveryRow) {
  Receiver r;
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  r.receive(4, linearZ(3), 3 * kT, /*lostPart=*/1);
  int undelivered = 0;
  for (int k = 0; k < kPredictorM; ++k) undelivered += r.assembler.rowFrame(k) == 4u ? 0 : 1;
  ASSERT_GT(undelivered, 0);
  // Z is linear in the poses: the delivered rows did not move, so neither did the others. Held, not predicted.
  EXPECT_TRUE(r.predictor.still());
  EXPECT_EQ(r.predictor.display(), r.views[2]);
  EXPECT_FALSE(r.predictor.nextDue().has_value());
}

TEST(FramePredictor, AStillFrameAfterAPredictionTakesItBack) {
  Receiver r;
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  ASSERT_EQ(r.predictor.advance(*r.predictor.nextDue()), FramePredictor::Step::Predicted);
  ASSERT_EQ(r.predictor.displayedFrame(), 4u);
  // The still frame came late (2 intervals): frame 3's Z again, nothing more predicted.
  r.receive(4, linearZ(3), 4 * kT);
  EXPECT_EQ(r.predictor.displayedFrame(), 4u);
  EXPECT_EQ(r.predictor.predictedFrames(), 0);
  EXPECT_EQ(r.predictor.display(), r.views[2]);
  EXPECT_FALSE(r.predictor.nextDue().has_value());
}

TEST(FramePredictor, GainDampsAndMaxFramesBounds) {
  PredictorSettings settings;
  settings.gain = 0.5;
  settings.maxFrames = 2;
  Receiver r(settings);
  for (std::uint32_t f = 1; f <= 3; ++f) r.receive(f, linearZ(f), (f - 1) * kT);
  const Eigen::MatrixXd velocity = r.views[2] - r.views[1];
  ASSERT_EQ(r.predictor.advance(*r.predictor.nextDue()), FramePredictor::Step::Predicted);
  EXPECT_LT((r.predictor.display() - (r.views[2] + 0.5 * velocity)).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(r.predictor.advance(*r.predictor.nextDue()), FramePredictor::Step::Predicted);
  EXPECT_EQ(r.predictor.displayedFrame(), 5u);
  EXPECT_EQ(r.predictor.advance(*r.predictor.nextDue()), FramePredictor::Step::Withdrawn);
  // A row's own prediction is bounded to maxFrames past its last value.
  EXPECT_LT((r.predictor.predictRow(0, 100) - (r.views[2].row(0) + 0.5 * 2 * velocity.row(0))).cwiseAbs().maxCoeff(),
            1e-12);
}

TEST(FramePredictor, PausesDoNotEnterTheInterval) {
  Receiver r;
  r.receive(1, linearZ(1), 0us);
  r.receive(2, linearZ(2), kT);
  r.receive(3, linearZ(3), kT + 1s);  // an idle pause: not an interval sample
  EXPECT_EQ(r.predictor.interval(), kT);
  r.receive(5, linearZ(5), kT + 1s + 2 * 40'000us);  // frame 4 lost: (80 ms) / 2 frames = 40 ms
  EXPECT_EQ(r.predictor.interval(), kT + (40'000us - kT) / 8);
}

TEST(FramePredictor, NoIntervalNoWholeFramePrediction) {
  Receiver r;
  r.receive(1, linearZ(1), 0us);
  r.receive(2, linearZ(2), 0us);  // same instant: below kMinInterval, no sample
  EXPECT_TRUE(r.predictor.moving());
  EXPECT_EQ(r.predictor.interval(), Micros{0});
  EXPECT_FALSE(r.predictor.nextDue().has_value());
}

}  // namespace
