// Tests the client's network impairment and timing over real UDP sockets on 127.0.0.1
// (src/session/net/client_datagram_channel.cpp, network_impairment.cpp): measured Bernoulli and burst loss match the
// setting, one-way latency on loopback is small, an impairment delay is applied by the precise timer, and impairment
// changes live or set before open take effect. Set-up: datagram_session.h.
#include "datagram_session.h"

#include "session/engine/session_clock.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

using namespace sc::session;
using namespace sc::session::testing;

/// Loss measured by the receiver statistics over 5000 real datagrams vs the impairment's setting.
void expectMeasuredLoss(const ImpairmentSettings& settings) {
  ClientDatagramOptions options;
  options.impairment = settings;
  Session s(options);
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(s.stream(1, 2500));  // 2 datagrams per frame
  const NetworkImpairment& impairment = *s.client.impairment();
  ASSERT_EQ(impairment.offered(), 5000u);                              // no loss on the real socket
  ASSERT_TRUE(waitUntil([&] { return impairment.inFlight() == 0; }));  // nothing held back
  const ReceiverReport report = s.client.report(sessionNow());
  const double simulated = static_cast<double>(impairment.dropped()) / 5000.0;
  EXPECT_NEAR(report.lossFraction, settings.loss, 0.02);
  // The statistics see exactly what the impairment dropped (up to losses at the very ends of the run).
  EXPECT_NEAR(report.lossFraction, simulated, 0.002);
  EXPECT_EQ(s.client.assembler()->accepted() + impairment.dropped(), 5000u);
  EXPECT_EQ(s.client.droppedDatagrams(), 0u);
}

TEST(DatagramChannel, MeasuredBernoulliLossMatchesSetting) {
  ImpairmentSettings settings;
  settings.loss = 0.2;
  settings.seed = 2024;
  expectMeasuredLoss(settings);
}

TEST(DatagramChannel, MeasuredBurstLossMatchesSetting) {
  ImpairmentSettings settings;
  settings.loss = 0.2;
  settings.burst = true;
  settings.burstLength = 3.0;
  settings.seed = 2025;
  expectMeasuredLoss(settings);
}

TEST(DatagramChannel, LatencyOnLoopbackIsSmall) {
  Session s;
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(s.stream(1, 100, 5));
  const ReceiverReport report = s.client.report(sessionNow());
  EXPECT_EQ(report.received, 200);
  EXPECT_EQ(report.cumulativeLost, 0);
  EXPECT_GE(report.latencyP50Ms, 0.0);
  EXPECT_LT(report.latencyP99Ms, 50.0);
  EXPECT_TRUE(std::isfinite(report.jitterMs));
}

TEST(DatagramChannel, ImpairmentDelayIsAppliedByThePreciseTimer) {
  ClientDatagramOptions options;
  options.impairment = ImpairmentSettings{};
  options.impairment->delay = Millis{30};
  Session s(options);
  ASSERT_TRUE(s.open());
  const Micros sentAt = sessionNow();
  s.host.sendFrame(1, frameZ(1), sentAt);
  ASSERT_TRUE(waitUntil([&] { return s.client.datagramsRead() == 2; }));
  EXPECT_EQ(s.client.assembler()->accepted(), 0u);  // held back
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }, 2000));
  EXPECT_GE((sessionNow() - sentAt).count(), 29'000);
  const ReceiverReport report = s.client.report(sessionNow());
  EXPECT_GE(report.latencyP50Ms, 29.0);
  EXPECT_LT(report.latencyP99Ms, 30.0 + 50.0);
}

TEST(DatagramChannel, ImpairmentChangesLiveWhileOpen) {
  Session s;  // no impairment at first
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(s.stream(1, 500));
  EXPECT_EQ(s.client.impairment(), nullptr);
  ReceiverReport report = s.client.report(sessionNow());
  EXPECT_EQ(report.received, 1000);
  EXPECT_NEAR(report.intervalLossFraction, 0.0, 1e-12);

  // 30% Bernoulli loss, switched on while open: the next interval measures it.
  ImpairmentSettings lossy;
  lossy.loss = 0.3;
  lossy.seed = 77;
  s.client.setImpairment(lossy);
  ASSERT_NE(s.client.impairment(), nullptr);
  ASSERT_TRUE(s.client.impairmentSettings().has_value());
  ASSERT_TRUE(s.stream(501, 1500));
  ASSERT_TRUE(waitUntil([&] { return s.client.impairment()->inFlight() == 0; }));
  report = s.client.report(sessionNow());
  EXPECT_NEAR(report.intervalLossFraction, 0.3, 0.03);
  EXPECT_EQ(s.client.impairment()->offered(), 3000u);

  // A delayed impairment holding datagrams is replaced: what it held is delivered at once, nothing is lost.
  ImpairmentSettings delayed;
  delayed.delay = Millis{400};
  s.client.setImpairment(delayed);
  const std::uint64_t acceptedBefore = s.client.assembler()->accepted();
  ASSERT_TRUE(s.stream(2001, 10));
  EXPECT_EQ(s.client.impairment()->inFlight(), 20u);
  EXPECT_EQ(s.client.assembler()->accepted(), acceptedBefore);
  s.client.setImpairment(std::nullopt);
  EXPECT_EQ(s.client.impairment(), nullptr);
  EXPECT_EQ(s.client.assembler()->accepted(), acceptedBefore + 20);

  // Back to no impairment: no loss again.
  (void)s.client.report(sessionNow());
  ASSERT_TRUE(s.stream(2011, 500));
  report = s.client.report(sessionNow());
  EXPECT_NEAR(report.intervalLossFraction, 0.0, 1e-12);
  EXPECT_EQ(s.client.droppedDatagrams(), 0u);
}

TEST(DatagramChannel, ImpairmentSetBeforeOpenIsUsedByOpen) {
  Session s;
  ImpairmentSettings lossy;
  lossy.loss = 0.5;
  s.client.setImpairment(lossy);
  EXPECT_EQ(s.client.impairment(), nullptr);  // not open yet
  ASSERT_TRUE(s.open());
  ASSERT_NE(s.client.impairment(), nullptr);
  EXPECT_DOUBLE_EQ(s.client.impairment()->settings().loss, 0.5);
}

}  // namespace
