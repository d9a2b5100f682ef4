// Tests src/session/engine/network_impairment.cpp: seeded loss (Bernoulli, Gilbert–Elliott), delay/jitter, reordering,
// duplication, determinism. Measured figures are printed so the report can quote them.
#include "session/engine/network_impairment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>

namespace {

using namespace sc::session;
using namespace std::chrono_literals;

QByteArray datagram(std::uint32_t index) {
  QByteArray bytes(8, '\0');
  std::memcpy(bytes.data(), &index, sizeof index);
  return bytes;
}

std::uint32_t indexOf(const QByteArray& bytes) {
  std::uint32_t index = 0;
  std::memcpy(&index, bytes.constData(), sizeof index);
  return index;
}

struct Delivery {
  std::uint32_t index;
  Millis at;
};

/// Offers n datagrams, one per millisecond (datagram i arrives at i ms), popping every millisecond until drained.
std::vector<Delivery> run(NetworkImpairment& net, int n) {
  std::vector<Delivery> out;
  for (Millis now{0};; ++now) {
    if (now.count() < n) net.push(datagram(static_cast<std::uint32_t>(now.count())), now);
    for (const QByteArray& bytes : net.popDue(now)) out.push_back({indexOf(bytes), now});
    if (now.count() >= n && net.inFlight() == 0) break;
  }
  return out;
}

/// Offers n datagrams and records which were lost (no delay, so a loss is visible at once).
std::vector<bool> lossPattern(NetworkImpairment& net, int n) {
  std::vector<bool> lost;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t before = net.dropped();
    net.push(datagram(static_cast<std::uint32_t>(i)), Millis{i});
    lost.push_back(net.dropped() != before);
    net.popDue(Millis{i});
  }
  return lost;
}

double meanBurst(const std::vector<bool>& lost) {
  int bursts = 0, losses = 0;
  for (std::size_t i = 0; i < lost.size(); ++i) {
    losses += lost[i] ? 1 : 0;
    if (lost[i] && (i == 0 || !lost[i - 1])) ++bursts;
  }
  return bursts > 0 ? static_cast<double>(losses) / bursts : 0.0;
}

TEST(NetworkImpairment, BernoulliLossWithinTwoPointsOver5000) {
  for (double loss : {0.02, 0.10, 0.20, 0.50}) {
    NetworkImpairment net({.loss = loss, .seed = 42});
    const std::vector<Delivery> out = run(net, 5000);
    const double measured = static_cast<double>(net.dropped()) / static_cast<double>(net.offered());
    NetworkImpairment again({.loss = loss, .seed = 42});
    std::printf("bernoulli loss %.2f: measured %.4f, mean burst %.3f\n", loss, measured,
                meanBurst(lossPattern(again, 5000)));
    EXPECT_EQ(net.offered(), 5000u);
    EXPECT_NEAR(measured, loss, 0.02) << "loss " << loss;
    EXPECT_EQ(net.delivered(), net.offered() - net.dropped());
    EXPECT_EQ(out.size(), net.delivered());
  }
}

TEST(NetworkImpairment, GilbertElliottStationaryLossAndBurstLength) {
  constexpr int kN = 100000;  // bursts correlate losses: the mean needs more samples than Bernoulli
  for (double loss : {0.05, 0.10, 0.20, 0.30}) {
    for (double burst : {3.0, 8.0}) {
      NetworkImpairment ge({.loss = loss, .burst = true, .burstLength = burst, .seed = 7});
      const std::vector<bool> lost = lossPattern(ge, kN);
      const double measured = static_cast<double>(ge.dropped()) / kN;
      const double geBurst = meanBurst(lost);
      NetworkImpairment bernoulli({.loss = loss, .seed = 7});
      const double bernoulliBurst = meanBurst(lossPattern(bernoulli, kN));
      std::printf("GE loss %.2f L %.0f: p %.4f r %.4f measured loss %.4f, mean burst %.2f (bernoulli %.2f)\n", loss,
                  burst, ge.goodToBad(), ge.badToGood(), measured, geBurst, bernoulliBurst);
      EXPECT_NEAR(ge.badToGood(), 1.0 / burst, 1e-12);
      EXPECT_NEAR(ge.goodToBad() / (ge.goodToBad() + ge.badToGood()), loss, 1e-12);
      EXPECT_NEAR(measured, loss, 0.02) << "loss " << loss << " burst " << burst;
      EXPECT_NEAR(geBurst, burst, 0.15 * burst) << "loss " << loss << " burst " << burst;
      EXPECT_GT(geBurst, bernoulliBurst + 1.0);
    }
  }
}

TEST(NetworkImpairment, ExtremeSettingsAreClamped) {
  NetworkImpairment all({.loss = 1.0, .seed = 1});
  run(all, 100);
  EXPECT_EQ(all.dropped(), 100u);
  EXPECT_EQ(all.delivered(), 0u);

  NetworkImpairment none({.loss = -0.5, .duplicate = 2.0, .seed = 1});
  EXPECT_EQ(run(none, 100).size(), 200u);
  EXPECT_EQ(none.duplicated(), 100u);

  // L = 1 allows at most 50 % stationary loss; beyond that p is clamped to 1 (realised loss L/(L+1)).
  NetworkImpairment clamped({.loss = 0.8, .burst = true, .burstLength = 1.0, .seed = 1});
  EXPECT_DOUBLE_EQ(clamped.goodToBad(), 1.0);
  EXPECT_DOUBLE_EQ(clamped.badToGood(), 1.0);
}

TEST(NetworkImpairment, SameSeedSameOutputOtherSeedDifferent) {
  const ImpairmentSettings base{.loss = 0.1,
                                .burst = true,
                                .burstLength = 3.0,
                                .delay = 5ms,
                                .jitter = 4ms,
                                .reorder = 0.05,
                                .duplicate = 0.05,
                                .seed = 1234};
  auto deliveries = [](ImpairmentSettings settings) {
    NetworkImpairment net(settings);
    std::vector<std::pair<std::uint32_t, long long>> out;
    for (const Delivery& d : run(net, 3000)) out.emplace_back(d.index, d.at.count());
    return out;
  };
  const auto first = deliveries(base);
  EXPECT_EQ(first, deliveries(base));
  ImpairmentSettings other = base;
  other.seed = 1235;
  EXPECT_NE(first, deliveries(other));
}

TEST(NetworkImpairment, DelayAndUniformJitterStayInBounds) {
  NetworkImpairment net({.delay = 20ms, .jitter = 5ms, .seed = 3});
  const std::vector<Delivery> out = run(net, 5000);
  ASSERT_EQ(out.size(), 5000u);
  double sum = 0.0;
  long long lo = 1000, hi = -1000;
  for (const Delivery& d : out) {
    const long long latency = d.at.count() - d.index;
    lo = std::min(lo, latency);
    hi = std::max(hi, latency);
    sum += static_cast<double>(latency);
  }
  std::printf("uniform delay 20 +- 5 ms: min %lld max %lld mean %.3f\n", lo, hi, sum / 5000.0);
  EXPECT_EQ(lo, 15);
  EXPECT_EQ(hi, 25);
  EXPECT_NEAR(sum / 5000.0, 20.0, 0.3);
}

TEST(NetworkImpairment, NormalJitterIsTruncatedAtThreeSigma) {
  NetworkImpairment net({.delay = 30ms, .jitter = 4ms, .jitterShape = JitterShape::Normal, .seed = 5});
  const std::vector<Delivery> out = run(net, 5000);
  ASSERT_EQ(out.size(), 5000u);
  double sum = 0.0, sumSq = 0.0;
  for (const Delivery& d : out) {
    const double latency = static_cast<double>(d.at.count() - d.index);
    EXPECT_GE(latency, 30.0 - 12.0);
    EXPECT_LE(latency, 30.0 + 12.0);
    sum += latency;
    sumSq += latency * latency;
  }
  const double mean = sum / 5000.0;
  const double sd = std::sqrt(sumSq / 5000.0 - mean * mean);
  std::printf("normal delay 30 ms sigma 4 ms: mean %.3f sd %.3f\n", mean, sd);
  EXPECT_NEAR(mean, 30.0, 0.3);
  EXPECT_NEAR(sd, 4.0, 0.4);
}

TEST(NetworkImpairment, JitterNeverDeliversBeforeArrival) {
  NetworkImpairment net({.jitter = 10ms, .seed = 9});
  for (const Delivery& d : run(net, 2000)) EXPECT_GE(d.at.count(), static_cast<long long>(d.index));
}

TEST(NetworkImpairment, ReorderingMatchesSetting) {
  NetworkImpairment net({.reorder = 0.10, .reorderGap = 10ms, .seed = 11});
  const std::vector<Delivery> out = run(net, 5000);
  ASSERT_EQ(out.size(), 5000u);
  // A datagram is out of order when a later-offered one was delivered before it.
  int outOfOrder = 0;
  std::uint32_t newest = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (i > 0 && out[i].index < newest) ++outOfOrder;
    newest = std::max(newest, out[i].index);
  }
  const double fraction = static_cast<double>(net.reordered()) / 5000.0;
  std::printf("reorder 0.10: selected %.4f, measured out-of-order %.4f\n", fraction, outOfOrder / 5000.0);
  EXPECT_NEAR(fraction, 0.10, 0.02);
  EXPECT_NEAR(outOfOrder / 5000.0, 0.10, 0.02);
}

TEST(NetworkImpairment, DuplicationMatchesSetting) {
  NetworkImpairment net({.duplicate = 0.05, .seed = 13});
  const std::vector<Delivery> out = run(net, 5000);
  std::map<std::uint32_t, int> copies;
  for (const Delivery& d : out) ++copies[d.index];
  int twice = 0;
  for (const auto& [index, count] : copies) {
    EXPECT_LE(count, 2);
    twice += count == 2 ? 1 : 0;
  }
  std::printf("duplicate 0.05: measured %.4f\n", twice / 5000.0);
  EXPECT_EQ(copies.size(), 5000u);
  EXPECT_EQ(static_cast<std::uint64_t>(twice), net.duplicated());
  EXPECT_EQ(net.delivered(), 5000u + net.duplicated());
  EXPECT_NEAR(twice / 5000.0, 0.05, 0.01);
}

TEST(NetworkImpairment, ReleasesInDeliveryOrderAndReportsNextDue) {
  NetworkImpairment net({.delay = 10ms, .seed = 1});
  EXPECT_EQ(net.nextDue(), Millis::max());
  net.push(datagram(1), 0ms);
  net.push(datagram(2), 0ms);
  net.push(datagram(3), 2ms);
  EXPECT_EQ(net.nextDue(), 10ms);
  EXPECT_TRUE(net.popDue(9ms).empty());
  const std::vector<QByteArray> first = net.popDue(10ms);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(indexOf(first[0]), 1u);  // same instant: offer order
  EXPECT_EQ(indexOf(first[1]), 2u);
  EXPECT_EQ(net.nextDue(), 12ms);
  EXPECT_EQ(net.popDue(100ms).size(), 1u);
  EXPECT_EQ(net.inFlight(), 0u);
}

}  // namespace
