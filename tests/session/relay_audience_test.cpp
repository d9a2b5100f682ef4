// The viewers' figures back to the host (relay_message.h Stats, engine/relay_audience.h; issue 18): the 92-byte
// message round-trips; malformed ones are dropped and counted; the aggregate spreads loss, latency and distortion
// across the viewers that reported in the last 10 s; the number of viewers tracked is bounded.
#include "session/engine/relay_audience.h"

#include <gtest/gtest.h>

#include <limits>

namespace sc::session {
namespace {

RelayStats statsOf(std::uint64_t viewer, std::uint64_t applied, std::uint64_t lost, double p99) {
  RelayStats s;
  s.viewer = viewer;
  s.applied = applied;
  s.lost = lost;
  s.latencyP50Ms = p99 / 2;
  s.latencyP99Ms = p99;
  return s;
}

TEST(RelayStats, RoundTripsAndRefusesMalformedMessages) {
  RelayStats s = statsOf(0xabcdef0123456789u, 900, 100, 3.5);
  s.concealed = 12;
  s.distortions = 7;
  s.distortionMeanPct = 0.25;
  s.distortionMaxPct = 1.5;
  const QByteArray message = encodeRelayStats(s);
  ASSERT_EQ(message.size(), kRelayStatsSize);
  EXPECT_EQ(relayKind(message), RelayKind::Stats);
  const std::optional<RelayStats> decoded = decodeRelayStats(message);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->viewer, s.viewer);
  EXPECT_EQ(decoded->applied, 900u);
  EXPECT_EQ(decoded->lost, 100u);
  EXPECT_EQ(decoded->latencyP99Ms, 3.5);
  EXPECT_EQ(decoded->concealed, 12u);
  EXPECT_EQ(decoded->distortions, 7u);
  EXPECT_EQ(decoded->distortionMeanPct, 0.25);
  EXPECT_EQ(decoded->distortionMaxPct, 1.5);
  for (qsizetype size = 0; size < message.size(); ++size) EXPECT_FALSE(decodeRelayStats(message.first(size)));
  EXPECT_FALSE(decodeRelayStats(QByteArray(message + QByteArray(1, '\0'))));
  QByteArray negative = message;
  negative[52] = static_cast<char>(0xbf);  // latencyP99 becomes negative (sign bit)
  EXPECT_FALSE(decodeRelayStats(negative));
  negative = message;
  negative[84] = static_cast<char>(0xbf);  // distortionMax becomes negative
  EXPECT_FALSE(decodeRelayStats(negative));
  RelayStats huge = s;
  huge.latencyP99Ms = std::numeric_limits<double>::infinity();
  EXPECT_EQ(decodeRelayStats(encodeRelayStats(huge))->latencyP99Ms, 0.0);  // the encoder never sends non-finite
}

TEST(RelayAudience, AggregatesTheViewersThatReportedRecently) {
  RelayAudience audience;
  const Micros t0{1'000'000};
  EXPECT_TRUE(audience.onStats(encodeRelayStats(statsOf(1, 100, 0, 2.0)), t0));
  EXPECT_TRUE(audience.onStats(encodeRelayStats(statsOf(2, 90, 10, 4.0)), t0));
  EXPECT_TRUE(audience.onStats(encodeRelayStats(statsOf(3, 50, 50, 8.0)), t0 + Micros{5'000'000}));
  EXPECT_TRUE(audience.onStats(encodeRelayStats(statsOf(1, 200, 0, 1.0)), t0 + Micros{5'000'000}));  // newer
  EXPECT_FALSE(audience.onStats(QByteArray("short"), t0));
  RelayAudienceSummary s = audience.summary(t0 + Micros{5'000'000});
  EXPECT_EQ(s.viewers, 3);
  EXPECT_EQ(s.lossFraction.min, 0.0);
  EXPECT_DOUBLE_EQ(s.lossFraction.median, 0.1);
  EXPECT_DOUBLE_EQ(s.lossFraction.max, 0.5);
  EXPECT_EQ(s.latencyP99Ms.min, 1.0);
  EXPECT_EQ(s.latencyP99Ms.max, 8.0);
  EXPECT_EQ(s.malformed, 1);
  s = audience.summary(t0 + Micros{12'000'000});  // viewer 2 silent for 12 s
  EXPECT_EQ(s.viewers, 2);
}

TEST(RelayAudience, SpreadsTheDistortionOfTheViewersThatMeasuredIt) {
  RelayAudience audience;
  const Micros t0{1'000'000};
  const auto measured = [](std::uint64_t viewer, double mean, double max, std::uint64_t concealed) {
    RelayStats s = statsOf(viewer, 100, 0, 2.0);
    s.distortions = 5;
    s.distortionMeanPct = mean;
    s.distortionMaxPct = max;
    s.concealed = concealed;
    return encodeRelayStats(s);
  };
  EXPECT_TRUE(audience.onStats(measured(1, 0.0, 0.0, 0), t0));
  EXPECT_TRUE(audience.onStats(measured(2, 0.5, 2.0, 3), t0));
  EXPECT_TRUE(audience.onStats(measured(3, 0.1, 0.4, 4), t0));
  EXPECT_TRUE(audience.onStats(encodeRelayStats(statsOf(4, 100, 0, 2.0)), t0));  // no level: nothing measured
  const RelayAudienceSummary s = audience.summary(t0);
  EXPECT_EQ(s.viewers, 4);
  EXPECT_EQ(s.distortionViewers, 3);
  EXPECT_EQ(s.distortionMeanPct.min, 0.0);
  EXPECT_EQ(s.distortionMeanPct.median, 0.1);
  EXPECT_EQ(s.distortionMeanPct.max, 0.5);
  EXPECT_EQ(s.distortionMaxPct.max, 2.0);
  EXPECT_EQ(s.concealed, 7);
}

TEST(RelayAudience, TracksABoundedNumberOfViewers) {
  RelayAudience audience;
  Micros now{0};
  for (int i = 0; i < kMaxTrackedViewers + 50; ++i) {
    now += Micros{1};
    audience.onStats(encodeRelayStats(statsOf(static_cast<std::uint64_t>(i), 10, 0, 1.0)), now);
  }
  EXPECT_EQ(audience.summary(now).viewers, kMaxTrackedViewers);
}

}  // namespace
}  // namespace sc::session
