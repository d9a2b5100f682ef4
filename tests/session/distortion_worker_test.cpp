// Tests src/session/net/distortion_worker.cpp: the live distortion is measured on a worker thread while the calling
// thread's event loop keeps turning (issue 19 item 3: the desktop client's GUI thread never waits for it), one batch
// at a time, with the same figures as distortionPercent on the level the batch holds. No timing is asserted: the
// bounds are generous deadlines for the event loop to turn at all.
#include "session/net/distortion_worker.h"

#include "spectral/display_level.h"
#include "spectral/hausdorff.h"
#include "spectral/quantized_basis.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>
#include <QtCore/QDeadlineTimer>
#include <QtCore/QTimer>

#include <atomic>
#include <chrono>
#include <random>
#include <thread>
#include <vector>

namespace {

using sc::session::DistortionPair;
using sc::session::DistortionWorker;

constexpr int kM = 6;

sc::spectral::SharedDisplayLevel smallLevel() {
  const sc::testing::GeneratedMesh mesh = sc::testing::icosphere(2);
  sc::spectral::ResolutionLevel level;
  level.restV = mesh.V;
  level.F = mesh.F;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 0.1);
  Eigen::MatrixXd K(mesh.V.rows(), kM);
  for (Eigen::Index i = 0; i < K.rows(); ++i)
    for (Eigen::Index k = 0; k < kM; ++k) K(i, k) = normal(rng);
  level.K = sc::spectral::quantizeBasis(K);
  return sc::spectral::makeDisplayLevel(std::move(level));
}

DistortionPair pair(unsigned seed, double noise) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  DistortionPair p;
  p.displayedAny = true;
  p.exact.resize(kM, 3);
  p.shown.resize(kM, 3);
  for (Eigen::Index k = 0; k < kM; ++k) {
    for (int c = 0; c < 3; ++c) {
      p.exact(k, c) = uniform(rng);
      p.shown(k, c) = p.exact(k, c) + noise * uniform(rng);
    }
  }
  return p;
}

/// Turns the calling thread's event loop until `done()` or 30 s have passed.
template <typename Done>
bool spinUntil(Done done) {
  const QDeadlineTimer deadline(30'000);
  while (!done() && !deadline.hasExpired()) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 10);
    std::this_thread::yield();
  }
  return done();
}

TEST(DistortionWorker, MeasuresOffTheCallingThreadWhileItsEventLoopTurns) {
  std::atomic<bool> release{false};
  std::atomic<bool> entered{false};
  std::thread::id measuredOn;
  DistortionWorker worker(
      nullptr, [&](const sc::spectral::ResolutionLevel&, const Eigen::MatrixXd&, const Eigen::MatrixXd&, double) {
        measuredOn = std::this_thread::get_id();
        entered = true;
        while (!release) std::this_thread::yield();  // a measurement that lasts until the test says
        return 1.5;
      });
  std::vector<double> figures;
  int batches = 0;
  QObject::connect(&worker, &DistortionWorker::measured, [&](const std::vector<double>& percents) {
    figures = percents;
    ++batches;
  });
  ASSERT_TRUE(worker.start(smallLevel(), {pair(1, 0.1)}));

  // The calling thread's timers fire while the measurement runs (it would not turn at all if it ran here).
  int ticks = 0;
  QTimer ticker;
  QObject::connect(&ticker, &QTimer::timeout, [&] { ++ticks; });
  ticker.start(1);
  ASSERT_TRUE(spinUntil([&] { return entered.load() && ticks >= 5; }));
  EXPECT_TRUE(worker.measuring());
  EXPECT_TRUE(worker.busy());
  EXPECT_EQ(batches, 0);
  EXPECT_FALSE(worker.start(smallLevel(), {pair(2, 0.1)})) << "one batch at a time";

  release = true;
  ASSERT_TRUE(spinUntil([&] { return batches == 1; }));
  EXPECT_NE(measuredOn, std::this_thread::get_id());
  EXPECT_EQ(figures, std::vector<double>{1.5});
  EXPECT_FALSE(worker.measuring());
  // After its rest (3 × the batch's time) it takes the next batch.
  ASSERT_TRUE(spinUntil([&] { return !worker.busy(); }));
  EXPECT_TRUE(worker.start(smallLevel(), {pair(3, 0.1)}));
  ASSERT_TRUE(spinUntil([&] { return batches == 2; }));
}

TEST(DistortionWorker, GivesDistortionPercentOfEachPairOnTheLevelItHolds) {
  sc::spectral::SharedDisplayLevel level = smallLevel();
  const std::vector<DistortionPair> pairs{pair(4, 1e-3), pair(5, 0.0), pair(6, 0.3)};
  const double diagonal = sc::spectral::boundingBoxDiagonal(level->level.restV);
  std::vector<double> expected;
  for (const DistortionPair& p : pairs)
    expected.push_back(sc::session::distortionPercent(level->level, p.shown, p.exact, diagonal));
  ASSERT_EQ(expected[1], 0.0);
  ASSERT_GT(expected[2], expected[0]);

  DistortionWorker worker;
  std::vector<double> figures;
  QObject::connect(&worker, &DistortionWorker::measured,
                   [&](const std::vector<double>& percents) { figures = percents; });
  EXPECT_FALSE(worker.start(nullptr, pairs)) << "no level";
  EXPECT_FALSE(worker.start(level, {})) << "nothing to measure";
  ASSERT_TRUE(worker.start(level, pairs));
  level.reset();  // the batch holds the level: the view may drop it meanwhile
  ASSERT_TRUE(spinUntil([&] { return !figures.empty(); }));
  EXPECT_EQ(figures, expected);
}

TEST(DistortionWorker, DestroyedWhileMeasuringWaitsForThePairInFlightOnly) {
  std::atomic<int> measured{0};
  std::atomic<bool> release{false};
  bool delivered = false;
  std::thread releaser;
  {
    DistortionWorker worker(
        nullptr, [&](const sc::spectral::ResolutionLevel&, const Eigen::MatrixXd&, const Eigen::MatrixXd&, double) {
          ++measured;
          while (!release) std::this_thread::yield();
          return 0.0;
        });
    QObject::connect(&worker, &DistortionWorker::measured, [&](const std::vector<double>&) { delivered = true; });
    ASSERT_TRUE(worker.start(smallLevel(), {pair(7, 0.1), pair(8, 0.1), pair(9, 0.1)}));
    ASSERT_TRUE(spinUntil([&] { return measured.load() == 1; }));
    releaser = std::thread([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      release = true;
    });
  }  // the destructor sets the stop flag and joins: the two pairs left are dropped
  releaser.join();
  EXPECT_EQ(measured.load(), 1);
  QCoreApplication::processEvents();
  EXPECT_FALSE(delivered) << "nothing reaches a destroyed worker's connections";
}

}  // namespace
