// Tests src/session/engine/receiver_statistics.cpp: RFC 3550 extended sequence, loss fractions and jitter; rates, fps
// and latency percentiles over synthetic streams with injected time.
#include "session/engine/receiver_statistics.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace {

using namespace sc::session;
using namespace std::chrono_literals;
using Millis = std::chrono::milliseconds;

/// Records a datagram with zero transit and 100 payload bytes.
ArrivalKind feed(ReceiverStatistics& stats, std::uint16_t sequence, Micros at = 0us) {
  return stats.record(sequence, at, at, 100, 128);
}

TEST(ReceiverStatistics, JitterMatchesHandComputedRfc3550Example) {
  // S = 0, 20, 40, 60 ms; R = 100, 125, 138, 165 ms → transit 100, 105, 98, 105 → |D| = 5, 7, 7.
  // J1 = 5/16 = 0.3125; J2 = 0.3125 + (7 − 0.3125)/16 = 0.73046875; J3 = J2 + (7 − J2)/16 = 1.122314453125 ms.
  ReceiverStatistics stats;
  const long long sent[] = {0, 20, 40, 60};
  const long long arrived[] = {100, 125, 138, 165};
  const double expected[] = {0.0, 0.3125, 0.73046875, 1.122314453125};
  for (int i = 0; i < 4; ++i) {
    stats.record(static_cast<std::uint16_t>(i), Millis{sent[i]}, Millis{arrived[i]}, 100, 128);
    EXPECT_DOUBLE_EQ(stats.peek(Millis{arrived[i]}).jitterMs, expected[i]) << "after datagram " << i;
  }
}

TEST(ReceiverStatistics, ConstantTransitHasNoJitter) {
  ReceiverStatistics stats;
  for (int i = 0; i < 100; ++i) stats.record(static_cast<std::uint16_t>(i), Millis{10 * i}, Millis{10 * i + 3}, 1, 1);
  EXPECT_DOUBLE_EQ(stats.peek(1s).jitterMs, 0.0);
}

TEST(ReceiverStatistics, LossAndExtendedSequenceAcrossWrap) {
  ReceiverStatistics stats;
  // 65530..65535 then 0..9, missing 65533, 2 and 3.
  for (int s : {65530, 65531, 65532, 65534})
    EXPECT_EQ(feed(stats, static_cast<std::uint16_t>(s)), ArrivalKind::InOrder);
  ReceiverReport first = stats.report(0us);
  EXPECT_EQ(first.extendedHighest, 65534u);
  EXPECT_EQ(first.expected, 5);
  EXPECT_EQ(first.received, 4);
  EXPECT_DOUBLE_EQ(first.intervalLossFraction, 1.0 / 5.0);
  EXPECT_EQ(first.fractionLost, 256 / 5);

  for (int s : {65535, 0, 1, 4, 5, 6, 7, 8, 9})
    EXPECT_EQ(feed(stats, static_cast<std::uint16_t>(s)), ArrivalKind::InOrder);
  ReceiverReport second = stats.report(0us);
  EXPECT_EQ(second.extendedHighest, 65536u + 9u);
  EXPECT_EQ(second.expected, 16);
  EXPECT_EQ(second.received, 13);
  EXPECT_EQ(second.cumulativeLost, 3);
  EXPECT_DOUBLE_EQ(second.lossFraction, 3.0 / 16.0);
  EXPECT_DOUBLE_EQ(second.intervalLossFraction, 2.0 / 11.0);
  EXPECT_EQ(second.fractionLost, 512 / 11);

  // An interval with nothing lost reports 0.
  feed(stats, 10);
  EXPECT_EQ(stats.report(0us).fractionLost, 0);
}

TEST(ReceiverStatistics, ManyWrapsCountCycles) {
  ReceiverStatistics stats;
  for (std::uint32_t n = 0; n < 3u * 65536u + 10u; ++n) feed(stats, static_cast<std::uint16_t>(n));
  const ReceiverReport r = stats.peek(0us);
  EXPECT_EQ(r.extendedHighest, 3u * 65536u + 9u);
  EXPECT_EQ(r.expected, 3 * 65536 + 10);
  EXPECT_EQ(r.cumulativeLost, 0);
}

TEST(ReceiverStatistics, LateAndDuplicateAcrossWrap) {
  ReceiverStatistics stats;
  EXPECT_EQ(feed(stats, 65534), ArrivalKind::InOrder);
  EXPECT_EQ(feed(stats, 0), ArrivalKind::InOrder);   // 65535 missing so far
  EXPECT_EQ(feed(stats, 65535), ArrivalKind::Late);  // fills the gap, behind the wrap
  EXPECT_EQ(feed(stats, 65535), ArrivalKind::Duplicate);
  EXPECT_EQ(feed(stats, 0), ArrivalKind::Duplicate);
  EXPECT_EQ(feed(stats, 1), ArrivalKind::InOrder);
  const ReceiverReport r = stats.peek(0us);
  EXPECT_EQ(r.expected, 4);
  EXPECT_EQ(r.received, 4);
  EXPECT_EQ(r.cumulativeLost, 0);
  EXPECT_EQ(r.late, 1u);
  EXPECT_EQ(r.duplicates, 2u);
}

TEST(ReceiverStatistics, DuplicateDetectionForgetsOldSlots) {
  ReceiverStatistics stats;
  // After kHistory numbers the bitmap slots are reused; a fresh number in a reused slot is not a duplicate.
  for (int n = 0; n < 3 * ReceiverStatistics::kHistory; n += 7) feed(stats, static_cast<std::uint16_t>(n));
  for (int n = 3 * ReceiverStatistics::kHistory - 50; n < 3 * ReceiverStatistics::kHistory; ++n)
    if (n % 7 != 0) {
      EXPECT_NE(feed(stats, static_cast<std::uint16_t>(n)), ArrivalKind::Duplicate) << n;
    }
  EXPECT_EQ(stats.peek(0us).duplicates, 0u);
}

TEST(ReceiverStatistics, ImplausibleJumpIsIgnoredUnlessConfirmed) {
  ReceiverStatistics stats;
  feed(stats, 10);
  feed(stats, 11);
  EXPECT_EQ(feed(stats, 20000), ArrivalKind::Jump);
  EXPECT_EQ(feed(stats, 12), ArrivalKind::InOrder);
  EXPECT_EQ(stats.peek(0us).expected, 3);
  // A sender restart: two consecutive numbers far away restart the sequence tracking (RFC 3550 A.1).
  EXPECT_EQ(feed(stats, 40000), ArrivalKind::Jump);
  EXPECT_EQ(feed(stats, 40001), ArrivalKind::InOrder);
  feed(stats, 40003);
  const ReceiverReport r = stats.peek(0us);
  EXPECT_EQ(r.jumps, 2u);
  EXPECT_EQ(r.expected, 3);
  EXPECT_EQ(r.received, 2);
}

TEST(ReceiverStatistics, KbpsAndFpsOverSyntheticStream) {
  // 25 frames per second (every 40 ms), two datagrams per frame of 374 payload bytes, 402 on the wire, for 3 s.
  ReceiverStatistics stats;
  std::uint16_t sequence = 0;
  for (int k = 0; k < 75; ++k) {
    const Micros at = Millis{40 * k};
    for (int part = 0; part < 2; ++part) stats.record(sequence++, at, at, 374, 402);
    stats.recordFrame(at);
  }
  const ReceiverReport r = stats.peek(Millis{2960});  // window (1.96 s, 2.96 s]: frames 50..74
  std::printf("25 fps x 2 x 374 B: payload %.2f kbit/s, wire %.2f kbit/s, %.2f fps\n", r.payloadKbps, r.wireKbps,
              r.framesPerSecond);
  EXPECT_DOUBLE_EQ(r.framesPerSecond, 25.0);
  EXPECT_DOUBLE_EQ(r.payloadKbps, 25 * 2 * 374 * 8 / 1000.0);
  EXPECT_DOUBLE_EQ(r.wireKbps, 25 * 2 * 402 * 8 / 1000.0);
  // Two seconds after the stream stops, the window is empty.
  const ReceiverReport later = stats.peek(Millis{5000});
  EXPECT_DOUBLE_EQ(later.framesPerSecond, 0.0);
  EXPECT_DOUBLE_EQ(later.payloadKbps, 0.0);
}

TEST(ReceiverStatistics, RateMeterWindowIsHalfOpen) {
  RateMeter meter(Micros{1'000'000});
  meter.add(0us, 100);
  meter.add(500ms, 10);
  EXPECT_EQ(meter.sum(999ms), 110u);
  EXPECT_EQ(meter.sum(1000ms), 10u);  // (0, 1 s]: the entry at 0 has left
  EXPECT_DOUBLE_EQ(meter.kilobitsPerSecond(1000ms), 0.08);
}

TEST(ReceiverStatistics, LatencyPercentilesByNearestRank) {
  ReceiverStatistics stats;
  // Latencies 1..100 ms, arriving in a scrambled order of sizes.
  for (int i = 0; i < 100; ++i) {
    const int latencyMs = 1 + (i * 37) % 100;
    stats.record(static_cast<std::uint16_t>(i), Millis{1000 * i}, Millis{1000 * i + latencyMs}, 1, 1);
  }
  const ReceiverReport r = stats.peek(200s);
  EXPECT_DOUBLE_EQ(r.latencyP50Ms, 50.0);
  EXPECT_DOUBLE_EQ(r.latencyP99Ms, 99.0);
  EXPECT_DOUBLE_EQ(r.latencyMaxMs, 100.0);
}

TEST(ReceiverStatistics, LatencyKeepsTheLastSamplesAndSubMillisecondResolution) {
  ReceiverStatistics stats(Micros{1'000'000}, 10);
  for (int i = 0; i < 50; ++i) stats.record(static_cast<std::uint16_t>(i), Millis{i}, Millis{i} + Micros{5000}, 1, 1);
  for (int i = 50; i < 60; ++i) stats.record(static_cast<std::uint16_t>(i), Millis{i}, Millis{i} + Micros{250}, 1, 1);
  const ReceiverReport r = stats.peek(1s);
  EXPECT_DOUBLE_EQ(r.latencyP50Ms, 0.25);
  EXPECT_DOUBLE_EQ(r.latencyP99Ms, 0.25);
  EXPECT_DOUBLE_EQ(r.latencyMaxMs, 5.0);
}

TEST(ReceiverStatistics, EmptyReportIsZero) {
  ReceiverStatistics stats;
  const ReceiverReport r = stats.peek(0us);
  EXPECT_EQ(r.expected, 0);
  EXPECT_EQ(r.received, 0);
  EXPECT_DOUBLE_EQ(r.lossFraction, 0.0);
  EXPECT_DOUBLE_EQ(r.latencyP99Ms, 0.0);
}

}  // namespace
