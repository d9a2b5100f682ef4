// Tests src/session/engine/link_rate.cpp (the emulated link's token bucket and bounded queue, issue 17 item 1) and
// its composition in NetworkImpairment: exact departure times on a fake clock, tail drop when the queue is full,
// the stream's share of the same bucket, the long-run rate, determinism.
#include "session/engine/link_rate.h"
#include "session/engine/network_impairment.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <vector>

namespace {

using namespace sc::session;
using namespace std::chrono_literals;

/// A link at `bitsPerSecond` with the automatic burst and queue.
LinkRateSettings atRate(double bitsPerSecond) {
  LinkRateSettings settings;
  settings.bitsPerSecond = bitsPerSecond;
  return settings;
}

/// 8 Mbit/s: one byte per microsecond, so every time below is exact. Burst 3000 B, queue 10 000 B, no overhead.
LinkRateSettings exactLink() {
  return {.bitsPerSecond = 8e6, .burstBytes = 3000, .queueBytes = 10000, .datagramOverheadBytes = 0};
}

TEST(LinkRate, BurstLeavesAtOnceThenOneDatagramPerItsSerialisationTime) {
  LinkRate link(exactLink());
  std::vector<Micros> departures;
  for (int i = 0; i < 6; ++i) departures.push_back(*link.admit(1000, 0us));
  EXPECT_EQ(departures, (std::vector<Micros>{0us, 0us, 0us, 1000us, 2000us, 3000us}));
  EXPECT_EQ(link.backlog(0us), 3000u);
  // Idle for 10 ms: the bucket is full again and the next burst leaves at once.
  EXPECT_EQ(*link.admit(1000, 10000us), 10000us);
  EXPECT_EQ(link.backlog(10000us), 0u);
}

TEST(LinkRate, FullQueueDropsAtTheTailAndDropsUseNoCapacity) {
  LinkRate link(exactLink());
  int admitted = 0;
  std::optional<Micros> last;
  for (int i = 0; i < 20; ++i) {
    const std::optional<Micros> departure = link.admit(1000, 0us);
    if (!departure) continue;
    ++admitted;
    last = departure;
  }
  // 3 in the burst, then 10 queued (the 13th leaves at 10 ms = 10 000 B queued ahead); the other 7 dropped.
  EXPECT_EQ(admitted, 13);
  EXPECT_EQ(*last, 10000us);
  EXPECT_EQ(link.dropped(), 7u);
  EXPECT_EQ(link.datagramsAdmitted(), 13u);
  // The drops did not advance the queue: at 5 ms the next one waits 6 ms (5 ms still queued ahead + its own 1 ms).
  EXPECT_EQ(*link.admit(1000, 5000us), 11000us);
}

TEST(LinkRate, OverheadIsChargedPerDatagram) {
  LinkRateSettings settings = exactLink();
  settings.datagramOverheadBytes = 28;
  LinkRate link(settings);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(*link.admit(972, 0us), 0us);  // 3 × 1000 B charged: the burst
  EXPECT_EQ(*link.admit(972, 0us), 1000us);
  EXPECT_EQ(link.datagramBytes(), 4000u);
}

TEST(LinkRate, StreamAndDatagramsShareOneBucket) {
  LinkRate link(exactLink());
  EXPECT_EQ(link.available(0us), 3000u);
  link.consume(3000, 0us);
  EXPECT_EQ(link.available(0us), 0u);
  EXPECT_EQ(link.availableAt(1000, 0us), 1000us);
  EXPECT_EQ(link.available(500us), 500u);
  // A datagram now waits for the bytes the stream took.
  EXPECT_EQ(*link.admit(1000, 0us), 1000us);
  // And the stream waits for the datagram: 1000 B are available again at 2 ms, the whole burst at 4 ms.
  EXPECT_EQ(link.available(1000us), 0u);
  EXPECT_EQ(link.availableAt(1000, 1000us), 2000us);
  EXPECT_EQ(link.availableAt(1'000'000, 1000us), 4000us);  // capped at the burst
  EXPECT_EQ(link.available(9000us), 3000u);
  EXPECT_EQ(link.streamBytes(), 3000u);
}

TEST(LinkRate, StreamReaderWokenEveryMillisecondKeepsTheRate) {
  const double rate = 20e6;
  LinkRate link(atRate(rate));
  std::uint64_t read = 0;
  const Micros end = 2'000'000us;
  for (Micros now = 0us; now < end; now += 1000us) {
    const std::size_t take = link.available(now);
    link.consume(take, now);
    read += take;
  }
  const double expected = rate / 8.0 * 2.0 + link.burstBytes();
  std::printf("stream at 20 Mbit/s, 1 ms reads for 2 s: %llu bytes (rate·T + burst = %.0f)\n",
              static_cast<unsigned long long>(read), expected);
  EXPECT_NEAR(static_cast<double>(read), expected, 0.001 * expected);
}

TEST(LinkRate, FloodedLinkDeliversTheRateAndDropsTheRest) {
  // Twice the link's rate offered for 5 s: 1000 B datagrams every 200 µs (40 Mbit/s) into 20 Mbit/s.
  LinkRateSettings settings = atRate(20e6);
  settings.datagramOverheadBytes = 0;
  LinkRate link(settings);
  Micros lastDeparture{0};
  std::uint64_t admittedBytes = 0;
  for (Micros now = 0us; now < 5'000'000us; now += 200us) {
    if (const std::optional<Micros> departure = link.admit(1000, now)) {
      EXPECT_GE(*departure, lastDeparture);  // FIFO
      EXPECT_GE(*departure, now);
      lastDeparture = *departure;
      admittedBytes += 1000;
    }
  }
  const double rateMeasured = static_cast<double>(admittedBytes - link.burstBytes()) * 8.0 /
                              (static_cast<double>(lastDeparture.count()) * 1e-6);
  std::printf("flooded 20 Mbit/s link: %.3f Mbit/s through, %llu of %d dropped\n", rateMeasured / 1e6,
              static_cast<unsigned long long>(link.dropped()), 25000);
  EXPECT_NEAR(rateMeasured, 20e6, 0.01 * 20e6);
  // Through: rate·T + burst + the queue still full at the end; the rest dropped.
  const double through = (20e6 / 8.0 * 5.0 + link.burstBytes() + link.queueBytes()) / 1000.0;
  EXPECT_NEAR(static_cast<double>(link.dropped()), 25000.0 - through, 3.0);
  EXPECT_LE(link.backlog(5'000'000us), link.queueBytes());
}

TEST(LinkRate, SettingsAreClampedAndAutomaticSizesFollowTheRate) {
  const LinkRate slow(atRate(1e6));
  EXPECT_EQ(slow.burstBytes(), 32u * 1024u);
  EXPECT_EQ(slow.queueBytes(), 64u * 1024u);
  const LinkRate fast(atRate(1e9));
  EXPECT_EQ(fast.burstBytes(), 500'000u);     // 4 ms at 1 Gbit/s
  EXPECT_EQ(fast.queueBytes(), 25'000'000u);  // 200 ms
  LinkRateSettings odd = atRate(-5.0);
  odd.burstBytes = 10;
  const LinkRate silly(odd);
  EXPECT_EQ(silly.bitsPerSecond(), LinkRate::kMinBitsPerSecond);
  EXPECT_EQ(silly.burstBytes(), LinkRate::kMinBurstBytes);
}

TEST(NetworkImpairmentRate, DelayIsAddedToTheDepartureAndQueueDropsAreCounted) {
  ImpairmentSettings settings{.delay = 20ms, .rate = exactLink(), .seed = 3};
  NetworkImpairment net(settings);
  ASSERT_NE(net.link(), nullptr);
  for (int i = 0; i < 20; ++i) net.push(QByteArray(1000, 'x'), 0ms);
  EXPECT_EQ(net.rateDropped(), 7u);
  EXPECT_EQ(net.dropped(), 7u);
  EXPECT_EQ(net.inFlight(), 13u);
  EXPECT_EQ(net.nextDue(), 20ms);
  EXPECT_EQ(net.popDue(20ms).size(), 3u);  // the burst
  EXPECT_EQ(net.popDue(21ms).size(), 1u);  // then one per millisecond
  EXPECT_EQ(net.popDue(30ms).size(), 9u);
  EXPECT_EQ(net.inFlight(), 0u);
}

TEST(NetworkImpairmentRate, SharedLinkIsChargedByBothPaths) {
  ImpairmentSettings settings;
  settings.rate = exactLink();
  auto link = std::make_shared<LinkRate>(settings.rate);
  NetworkImpairment net(settings, link);
  EXPECT_EQ(net.link(), link);
  link->consume(3000, 0us);              // the stream took the burst
  net.push(QByteArray(1000, 'x'), 0ms);  // so this datagram leaves at 1 ms
  EXPECT_TRUE(net.popDue(0ms).empty());
  EXPECT_EQ(net.nextDue(), 1ms);
}

TEST(NetworkImpairmentRate, SameSeedSameDeliveries) {
  const auto deliveries = [] {
    ImpairmentSettings settings{.loss = 0.1, .delay = 5ms, .jitter = 3ms, .seed = 42};
    settings.rate = {.bitsPerSecond = 2e6, .burstBytes = 4000, .queueBytes = 20000, .datagramOverheadBytes = 28};
    NetworkImpairment net(settings);
    std::vector<std::pair<long long, int>> out;
    for (Millis now{0}; now < 2000ms; ++now) {
      net.push(QByteArray(400 + static_cast<int>(now.count() % 700), 'x'), now);
      for (const QByteArray& bytes : net.popDue(now)) out.emplace_back(now.count(), static_cast<int>(bytes.size()));
    }
    return std::make_pair(out, net.rateDropped());
  };
  const auto first = deliveries();
  EXPECT_GT(first.second, 0u);  // the link was flooded (≈ 6 Mbit/s offered into 2)
  EXPECT_EQ(first, deliveries());
}

}  // namespace
