// Tests src/session/engine/distortion_probe.cpp: which displayed Z stands for a reference frame (hold-last at frame
// level, rest before anything, serial wrap, eviction), the Hausdorff distortion against a brute-force max-min, and the
// summary accumulator.
#include "session/engine/distortion_probe.h"

#include "spectral/hausdorff.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

using namespace sc::session;

constexpr int kM = 6;

Eigen::MatrixXd constantZ(double value) { return Eigen::MatrixXd::Constant(kM, 3, value); }

TEST(DistortionProbe, PairsUseTheLastZShownForTheNewestFrameNotAfterTheReference) {
  DistortionProbe probe;
  probe.reference(0, constantZ(9.0));  // before anything was displayed: the rest shape
  probe.displayed(1, constantZ(1.0));
  probe.displayed(1, constantZ(1.5));  // the last Z shown while frame 1 was current counts
  probe.displayed(2, constantZ(2.0));
  probe.displayed(4, constantZ(4.0));  // frame 3 was lost entirely
  probe.reference(1, constantZ(10.0));
  probe.reference(2, constantZ(20.0));
  probe.reference(3, constantZ(30.0));
  probe.reference(4, constantZ(40.0));

  const std::vector<DistortionPair> ready = probe.takeReady(4);  // frame 4 may still be receiving datagrams
  ASSERT_EQ(ready.size(), 4u);
  EXPECT_EQ(ready[0].frame, 0u);
  EXPECT_FALSE(ready[0].displayedAny);
  EXPECT_EQ(ready[0].shown, Eigen::MatrixXd::Zero(kM, 3));
  EXPECT_EQ(ready[0].exact, constantZ(9.0));
  EXPECT_EQ(ready[1].shownFrame, 1u);
  EXPECT_EQ(ready[1].shown, constantZ(1.5));
  EXPECT_EQ(ready[2].shownFrame, 2u);
  EXPECT_EQ(ready[2].shown, constantZ(2.0));
  EXPECT_EQ(ready[3].frame, 3u);
  EXPECT_EQ(ready[3].shownFrame, 2u);  // hold-last: frame 2 stayed on screen
  EXPECT_EQ(ready[3].shown, constantZ(2.0));
  EXPECT_EQ(ready[3].exact, constantZ(30.0));
  EXPECT_EQ(probe.pendingReferences(), 1u);

  probe.displayed(4, constantZ(4.5));
  EXPECT_TRUE(probe.takeReady(4).empty());
  const std::vector<DistortionPair> rest = probe.takeAll();  // end of the run
  ASSERT_EQ(rest.size(), 1u);
  EXPECT_EQ(rest[0].frame, 4u);
  EXPECT_EQ(rest[0].shown, constantZ(4.5));
  EXPECT_EQ(probe.pendingReferences(), 0u);
}

TEST(DistortionProbe, PredictedFramesCountAsShownUntilWithdrawn) {
  DistortionProbe probe;
  probe.displayed(1, constantZ(1.0));
  probe.displayed(2, constantZ(2.0));  // predicted frame 2 (frame 2 lost)
  probe.displayed(3, constantZ(3.0));  // a real frame 3
  probe.displayed(4, constantZ(4.0));  // predicted 4 and 5, then withdrawn: back to frame 3
  probe.displayed(5, constantZ(5.0));
  probe.withdraw(3);
  probe.displayed(3, constantZ(3.0));
  EXPECT_EQ(probe.historySize(), 3u);
  probe.reference(2, constantZ(0.0));
  probe.reference(4, constantZ(0.0));
  const std::vector<DistortionPair> ready = probe.takeAll();
  ASSERT_EQ(ready.size(), 2u);
  EXPECT_EQ(ready[0].shownFrame, 2u);  // the prediction was on screen for frame 2
  EXPECT_EQ(ready[0].shown, constantZ(2.0));
  EXPECT_EQ(ready[1].shownFrame, 3u);  // withdrawn: frame 3 is what shows from then on
  EXPECT_EQ(ready[1].shown, constantZ(3.0));
}

TEST(DistortionProbe, FrameNumbersWrap) {
  DistortionProbe probe;
  probe.displayed(0xfffffffeu, constantZ(1.0));
  probe.displayed(0xffffffffu, constantZ(2.0));
  probe.displayed(1, constantZ(3.0));  // frame 0 lost
  probe.reference(0, constantZ(0.5));
  probe.reference(0xfffffffeu, constantZ(0.5));
  const std::vector<DistortionPair> ready = probe.takeReady(1);
  ASSERT_EQ(ready.size(), 2u);
  EXPECT_EQ(ready[0].shownFrame, 0xffffffffu);
  EXPECT_EQ(ready[0].shown, constantZ(2.0));
  EXPECT_EQ(ready[1].shownFrame, 0xfffffffeu);
}

TEST(DistortionProbe, ReferencesOlderThanTheHistoryExpire) {
  DistortionProbe probe(4);
  for (std::uint32_t f = 1; f <= 10; ++f) probe.displayed(f, constantZ(f));
  EXPECT_EQ(probe.historySize(), 4u);
  probe.reference(3, constantZ(0.0));  // frames 1..6 were evicted
  probe.reference(8, constantZ(0.0));
  const std::vector<DistortionPair> ready = probe.takeReady(10);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].frame, 8u);
  EXPECT_EQ(ready[0].shown, constantZ(8.0));
  EXPECT_EQ(probe.expired(), 1u);
}

TEST(DistortionProbe, OutOfOrderDisplayKeepsTheHistorySorted) {
  DistortionProbe probe;
  probe.displayed(5, constantZ(5.0));
  probe.displayed(3, constantZ(3.0));
  probe.displayed(4, constantZ(4.0));
  probe.reference(4, constantZ(0.0));
  probe.reference(3, constantZ(0.0));
  const std::vector<DistortionPair> ready = probe.takeReady(5);
  ASSERT_EQ(ready.size(), 2u);
  EXPECT_EQ(ready[0].shown, constantZ(4.0));
  EXPECT_EQ(ready[1].shown, constantZ(3.0));
}

/// A small level: icosphere rest positions and a random reduced basis K (n' by kM).
sc::spectral::ResolutionLevel smallLevel() {
  const sc::testing::GeneratedMesh mesh = sc::testing::icosphere(2);
  sc::spectral::ResolutionLevel level;
  level.restV = mesh.V;
  level.F = mesh.F;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 0.1);
  Eigen::MatrixXd K(mesh.V.rows(), kM);
  for (Eigen::Index i = 0; i < K.rows(); ++i)
    for (Eigen::Index k = 0; k < kM; ++k) K(i, k) = normal(rng);
  level.K = sc::spectral::quantizeBasis(K);
  return level;
}

Eigen::MatrixXd randomZ(unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-scale, scale);
  Eigen::MatrixXd Z(kM, 3);
  for (Eigen::Index k = 0; k < kM; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = uniform(rng);
  return Z;
}

/// max over a of min over b of ‖a − b‖, both ways, by brute force.
double bruteForceHausdorff(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const auto oneSided = [](const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      double nearest = std::numeric_limits<double>::infinity();
      for (Eigen::Index j = 0; j < Q.rows(); ++j) nearest = std::min(nearest, (P.row(i) - Q.row(j)).norm());
      worst = std::max(worst, nearest);
    }
    return worst;
  };
  return std::max(oneSided(A, B), oneSided(B, A));
}

TEST(DistortionPercent, ZeroForIdenticalCoefficients) {
  const sc::spectral::ResolutionLevel level = smallLevel();
  const Eigen::MatrixXd Z = randomZ(1, 1.0);
  EXPECT_EQ(distortionPercent(level, Z, Z, sc::spectral::boundingBoxDiagonal(level.restV)), 0.0);
}

TEST(DistortionPercent, MatchesBruteForceMaxMin) {
  const sc::spectral::ResolutionLevel level = smallLevel();
  const double diagonal = sc::spectral::boundingBoxDiagonal(level.restV);
  const Eigen::MatrixXd exact = randomZ(2, 1.0);
  for (const double noise : {1e-3, 1e-2, 0.3}) {
    const Eigen::MatrixXd shown = exact + randomZ(3, noise);
    const double pct = distortionPercent(level, shown, exact, diagonal);
    const Eigen::MatrixXd K = level.K.Q.cast<double>() * level.K.scale.cast<double>().asDiagonal();
    const Eigen::MatrixXd Xs = level.restV + K * shown;
    const Eigen::MatrixXd Xe = level.restV + K * exact;
    const double expected = 100.0 * bruteForceHausdorff(Xs, Xe) / diagonal;
    EXPECT_GT(pct, 0.0) << noise;
    EXPECT_NEAR(pct, expected, 1e-9 * std::max(1.0, expected)) << noise;
  }
  EXPECT_TRUE(std::isnan(distortionPercent(level, exact, exact, 0.0)));
}

TEST(DistortionSummary, MaxMeanLastCount) {
  DistortionSummary summary;
  summary.add(1.0);
  summary.add(3.0);
  summary.add(std::numeric_limits<double>::quiet_NaN());  // ignored
  summary.add(2.0);
  EXPECT_EQ(summary.count, 3u);
  EXPECT_DOUBLE_EQ(summary.maxPct, 3.0);
  EXPECT_DOUBLE_EQ(summary.meanPct, 2.0);
  EXPECT_DOUBLE_EQ(summary.lastPct, 2.0);
  summary.reset();
  EXPECT_EQ(summary.count, 0u);
}

}  // namespace
