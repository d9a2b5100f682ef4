// Tests src/session/engine/recent_window.cpp and the recent figures of ReceiverStatistics (issue 16): latency
// percentiles and loss over the last 10 s on an injected clock, so a stall or a clean stretch long ago no longer
// sets the figure.
#include "session/engine/recent_window.h"
#include "session/engine/receiver_statistics.h"

#include <gtest/gtest.h>

namespace {

using namespace sc::session;
using namespace std::chrono_literals;
using Millis = std::chrono::milliseconds;

TEST(RecentSamples, PercentileCoversOnlyTheHalfOpenWindow) {
  RecentSamples samples(10s, 100);
  samples.add(0s, 900ms);  // a stall
  for (int i = 1; i <= 10; ++i) samples.add(Millis{1000 * i}, Millis{i});
  EXPECT_EQ(samples.count(10s), 10u) << "(0 s, 10 s]: the sample at 0 has left";
  EXPECT_DOUBLE_EQ(samples.percentileMs(10s, 0.99), 10.0);
  EXPECT_DOUBLE_EQ(samples.percentileMs(10s, 0.5), 5.0);
  EXPECT_EQ(samples.count(30s), 0u);
  EXPECT_DOUBLE_EQ(samples.percentileMs(30s, 0.99), 0.0) << "nothing arrived in the window";
}

TEST(RecentSamples, CapacityDropsTheOldest) {
  RecentSamples samples(10s, 3);
  for (int i = 1; i <= 5; ++i) samples.add(Millis{i}, Millis{100 * i});
  EXPECT_EQ(samples.count(5ms), 3u);
  EXPECT_DOUBLE_EQ(samples.percentileMs(5ms, 0.01), 300.0);
}

TEST(RecentLoss, CountsOnlyTheGrowthInsideTheWindow) {
  RecentLoss loss(10s, 100ms);
  // 100 s lossless at 10 per second, then 10 s where one in five is lost.
  std::int64_t expected = 0;
  std::int64_t received = 0;
  for (int i = 1; i <= 1000; ++i) loss.record(Millis{100 * i}, ++expected, ++received);
  EXPECT_DOUBLE_EQ(loss.fraction(100s, expected, received), 0.0);
  for (int i = 1001; i <= 1100; ++i) {
    ++expected;
    if (i % 5 != 1) loss.record(Millis{100 * i}, expected, ++received);
  }
  EXPECT_NEAR(loss.fraction(110s, expected, received), 0.2, 0.011);
  EXPECT_DOUBLE_EQ(loss.fraction(200s, expected, received), 0.0) << "nothing counted since the window opened";
  loss.restart();
  EXPECT_DOUBLE_EQ(loss.fraction(200s, 10, 5), 0.5) << "after a restart the counts start from zero";
}

TEST(ReceiverStatisticsRecent, AJoinStallLeavesTheLatencyAfterTheWindow) {
  ReceiverStatistics stats;
  std::uint16_t seq = 0;
  // The join: 100 datagrams that waited 2.5 s; then 60 s of 1 ms transit at 100 per second.
  for (int i = 0; i < 100; ++i, ++seq) stats.record(seq, Millis{i}, Millis{2500 + i}, 100, 128);
  for (int i = 0; i < 6000; ++i, ++seq) {
    const Micros at = Millis{3000 + 10 * i};
    stats.record(seq, at - 1ms, at, 100, 128);
  }
  const ReceiverReport r = stats.peek(Millis{3000 + 10 * 5999});  // the last arrival
  EXPECT_DOUBLE_EQ(r.latencyP99Ms, 2500.0) << "the last 8,192 samples still hold the stall";
  EXPECT_DOUBLE_EQ(r.recentLatencyP99Ms, 1.0);
  EXPECT_DOUBLE_EQ(r.recentLatencyP50Ms, 1.0);
  EXPECT_EQ(r.recentLatencySamples, 1000u) << "10 s at 100 per second";
}

TEST(ReceiverStatisticsRecent, TwentyPercentLossReadsTwentyPercentAfterALongCleanStretch) {
  ReceiverStatistics stats;
  std::uint16_t seq = 0;
  Micros at = 0us;
  // 10 minutes lossless at 50 datagrams per second (the sequence wraps), then 10 s with every fifth one lost.
  for (int i = 0; i < 30'000; ++i, ++seq, at += 20ms) stats.record(seq, at, at + 1ms, 100, 128);
  for (int i = 0; i < 500; ++i, ++seq, at += 20ms)
    if (i % 5 != 4) stats.record(seq, at, at + 1ms, 100, 128);
  const ReceiverReport r = stats.peek(at);
  EXPECT_NEAR(r.recentLossFraction, 0.2, 0.01);
  EXPECT_LT(r.lossFraction, 0.004) << "since the join the loss is diluted: 100 of 30,500";
}

TEST(ReceiverStatisticsRecent, ClearLatencyForgetsTheRecentSamples) {
  ReceiverStatistics stats;
  stats.record(0, 0ms, 5ms, 100, 128);
  stats.clearLatency();
  EXPECT_EQ(stats.peek(5ms).recentLatencySamples, 0u);
  EXPECT_DOUBLE_EQ(stats.peek(5ms).recentLatencyP99Ms, 0.0);
}

}  // namespace
