// What a relay viewer shows and how far it was from the exact shape (src/session/engine/relay_display.h, issue 18
// item 2) on an injected clock: hold-last and extrapolation of whole relayed frames, and the distortion of missed
// frames against exact references (0 on the frames the viewer got).
#include "session/engine/relay_display.h"
#include "spectral/hausdorff.h"
#include "spectral/quantized_basis.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace sc::session {
namespace {

using namespace std::chrono_literals;

constexpr int kM = 8;
constexpr Micros kT = 33'000us;  ///< the host's inter-frame interval in these tests

/// A handle moving at constant velocity: Z(f) = A + f·B.
Eigen::MatrixXd linearZ(std::uint32_t f) {
  Eigen::MatrixXd Z(kM, 3);
  for (int k = 0; k < kM; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = (0.2 * (c + 1) + 0.02 * f * (c - 1.0)) / (1.0 + k);
  return Z;
}

Micros frameTime(std::uint32_t f) { return Micros{static_cast<std::int64_t>(f) * kT}; }

/// A small level: random rest positions and a random K (n' by kM), quantised as a host's levels are.
spectral::ResolutionLevel smallLevel() {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 0.3);
  spectral::ResolutionLevel level;
  level.restV.resize(200, 3);
  for (Eigen::Index i = 0; i < level.restV.rows(); ++i)
    for (int c = 0; c < 3; ++c) level.restV(i, c) = normal(rng);
  Eigen::MatrixXd K(level.restV.rows(), kM);
  for (Eigen::Index i = 0; i < K.rows(); ++i)
    for (int k = 0; k < kM; ++k) K(i, k) = normal(rng);
  level.K = spectral::quantizeBasis(K);
  return level;
}

TEST(RelayDisplay, AViewerThatMissesFramesShowsDistortionOnThemAndNoneOnTheOnesItGot) {
  const spectral::ResolutionLevel level = smallLevel();
  const double diagonal = spectral::boundingBoxDiagonal(level.restV);
  RelayDisplay display(Concealment::HoldLast);
  for (std::uint32_t f = 1; f <= 10; ++f) {
    if (f != 4 && f != 5) display.applied(f, linearZ(f), frameTime(f));  // frames 4 and 5 never arrive
    EXPECT_EQ(display.display(), linearZ(f == 4 || f == 5 ? 3 : f));     // hold-last: the newest frame stays
    display.reference(f, linearZ(f));  // the exact references, as if the host stored a keyframe every frame
  }
  const std::vector<RelayDistortionSample> samples = display.measure(level, diagonal, 100);
  ASSERT_EQ(samples.size(), 10u);
  for (const RelayDistortionSample& s : samples) {
    SCOPED_TRACE(s.frame);
    if (s.frame == 4 || s.frame == 5) {
      EXPECT_EQ(s.shownFrame, 3u);  // frame 3 stood for them
      EXPECT_GT(s.percent, 0.0);
    } else {
      EXPECT_EQ(s.shownFrame, s.frame);
      EXPECT_EQ(s.percent, 0.0);  // relayed frames are exact: the same K, the same Z
    }
  }
  EXPECT_GT(samples[4].percent, samples[3].percent);  // two frames behind is further than one
  EXPECT_EQ(display.distortion().count, 10u);
  EXPECT_EQ(display.distortion().maxPct, samples[4].percent);
  EXPECT_EQ(display.counts().predicted, 0u);
  EXPECT_FALSE(display.nextDue());  // hold-last schedules nothing
}

TEST(RelayDisplay, AReferenceWaitsUntilItsFrameOrANewerOneArrivedAndIsTakenOnce) {
  const spectral::ResolutionLevel level = smallLevel();
  RelayDisplay display;
  display.applied(3, linearZ(3), frameTime(3));
  display.reference(1, linearZ(1));  // before the viewer's first frame: nothing to compare with
  display.reference(4, linearZ(4));
  display.reference(4, linearZ(4));  // the same keyframe read again
  EXPECT_TRUE(display.measure(level, 1.0).empty());
  EXPECT_EQ(display.counts().references, 2u);
  display.applied(4, linearZ(4), frameTime(4));
  const std::vector<RelayDistortionSample> samples = display.measure(level, 1.0);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].frame, 4u);
  EXPECT_EQ(samples[0].percent, 0.0);
  EXPECT_TRUE(display.measure(level, 1.0).empty());
}

TEST(RelayDisplay, ExtrapolationPredictsOverdueFramesAndALateFrameReplacesThePrediction) {
  const spectral::ResolutionLevel level = smallLevel();
  const double diagonal = spectral::boundingBoxDiagonal(level.restV);
  RelayDisplay display(Concealment::Extrapolate);
  for (std::uint32_t f = 1; f <= 5; ++f) display.applied(f, linearZ(f), frameTime(f));
  ASSERT_TRUE(display.nextDue());
  EXPECT_EQ(*display.nextDue(), frameTime(5) + Micros{kT.count() * 3 / 2});  // 1.5 intervals after frame 5
  EXPECT_EQ(display.advance(frameTime(5) + kT), FramePredictor::Step::None);
  // Frame 6 is overdue: dead reckoning shows it (exact for a handle at constant velocity).
  ASSERT_EQ(display.advance(frameTime(6) + kT / 2), FramePredictor::Step::Predicted);
  EXPECT_EQ(display.displayedFrame(), 6u);
  EXPECT_EQ(display.receivedFrame(), 5u);
  EXPECT_LT((display.display() - linearZ(6)).cwiseAbs().maxCoeff(), 1e-12);
  display.reference(6, linearZ(6));
  // Frame 6 arrives late, before 7: the exact frame replaces the prediction.
  const Eigen::MatrixXd late = linearZ(6) + Eigen::MatrixXd::Constant(kM, 3, 0.01);  // the handle turned a little
  display.applied(6, late, frameTime(6) + kT * 3 / 4);
  EXPECT_EQ(display.displayedFrame(), 6u);
  EXPECT_EQ(display.display(), late);
  const std::vector<RelayDistortionSample> samples = display.measure(level, diagonal);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].shownFrame, 6u);
  EXPECT_GT(samples[0].percent, 0.0);  // the reference says linearZ(6); what arrived (and was shown) differs
  EXPECT_EQ(display.counts().predicted, 1u);
}

TEST(RelayDisplay, ExtrapolationConcealsMissedFramesBetterThanHoldLastAndWithdrawsWhenTheStreamStops) {
  const spectral::ResolutionLevel level = smallLevel();
  const double diagonal = spectral::boundingBoxDiagonal(level.restV);
  RelayDisplay hold(Concealment::HoldLast);
  RelayDisplay predict(Concealment::Extrapolate);
  for (RelayDisplay* display : {&hold, &predict}) {
    for (std::uint32_t f = 1; f <= 5; ++f) display->applied(f, linearZ(f), frameTime(f));
    display->advance(frameTime(6) + kT / 2);  // frame 6 is lost
    display->reference(6, linearZ(6));
    display->applied(7, linearZ(7), frameTime(7));
  }
  const std::vector<RelayDistortionSample> held = hold.measure(level, diagonal);
  const std::vector<RelayDistortionSample> predicted = predict.measure(level, diagonal);
  ASSERT_EQ(held.size(), 1u);
  ASSERT_EQ(predicted.size(), 1u);
  EXPECT_EQ(held[0].shownFrame, 5u);
  EXPECT_EQ(predicted[0].shownFrame, 6u);
  EXPECT_GT(held[0].percent, 0.0);
  EXPECT_LT(predicted[0].percent, 1e-6 * held[0].percent + 1e-12);  // constant velocity: predicted exactly
  // The stream stops after frame 7: frames 8..11 are predicted, then the prediction is withdrawn (frame 7 again).
  int steps = 0;
  FramePredictor::Step step = FramePredictor::Step::None;
  while (predict.nextDue() && steps < 10) {
    step = predict.advance(*predict.nextDue());
    ++steps;
  }
  EXPECT_EQ(step, FramePredictor::Step::Withdrawn);
  EXPECT_EQ(predict.displayedFrame(), 7u);
  EXPECT_EQ(predict.display(), linearZ(7));
  EXPECT_EQ(predict.counts().withdrawn, 1u);
  EXPECT_EQ(predict.counts().predicted, 1u + 4u);
  // A reference of a withdrawn frame is paired with what is shown from then on (frame 7 held), not the prediction.
  predict.reference(9, linearZ(9));
  predict.applied(10, linearZ(10), frameTime(10) + 10 * kT);
  const std::vector<RelayDistortionSample> after = predict.measure(level, diagonal);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].shownFrame, 7u);
  EXPECT_GT(after[0].percent, 0.0);
}

TEST(RelayDisplay, MeasureKeepsTheNewestPairsAndCountsTheOthers) {
  const spectral::ResolutionLevel level = smallLevel();
  RelayDisplay display;
  for (std::uint32_t f = 1; f <= 6; ++f) {
    display.applied(f, linearZ(f), frameTime(f));
    display.reference(f, linearZ(f));
  }
  display.applied(7, linearZ(7), frameTime(7));
  const std::vector<RelayDistortionSample> samples = display.measure(level, 1.0, 2);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[0].frame, 5u);
  EXPECT_EQ(samples[1].frame, 6u);
  EXPECT_EQ(display.counts().skipped, 4u);
}

}  // namespace
}  // namespace sc::session
