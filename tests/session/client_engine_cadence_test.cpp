// Tests for the ClientEngine's timing rules (src/session/engine/client_engine_cadence.cpp) on a fake clock:
// heartbeat and StatsReport every second from the join, the host-silence timeout, lock renewals, one wake-up time.
#include "client_engine_fixture.h"

#include <cmath>
#include <limits>

namespace sc::session::test {
namespace {

constexpr Micros kSecond = ClientEngine::kSecond;

/// A sampler that counts its calls and reports fixed figures.
struct FakeReceiver {
  int calls = 0;
  ReceiverSampler sampler() {
    return [this](Micros) {
      ++calls;
      ReceiverSample s;
      s.report.received = 40;
      s.report.cumulativeLost = 2;
      s.report.jitterMs = 1.5;
      s.report.lossFraction = 0.5;  // since the join: not what the report carries
      s.report.recentLossFraction = std::numeric_limits<double>::quiet_NaN();
      s.report.latencyP50Ms = 900.0;
      s.report.latencyP99Ms = 2500.0;  // a join stall long ago
      s.report.recentLatencyP50Ms = -1.0;
      s.report.recentLatencyP99Ms = 1.25;
      s.framesApplied = 30;
      s.dropped = 4;
      return s;
    };
  }
};

TEST(ClientEngineCadence, HeartbeatAndStatsEverySecondFromTheJoin) {
  ClientEngine engine(config("a"));
  joinSession(engine, kT0);
  FakeReceiver receiver;
  EXPECT_EQ(engine.nextWakeUp(), kT0 + kSecond);
  EXPECT_TRUE(engine.tick(kT0 + kSecond - Micros{1}, receiver.sampler()).empty()) << "not yet due";
  EXPECT_EQ(receiver.calls, 0);
  for (std::uint32_t beat = 0; beat < 3; ++beat) {
    const Micros at = kT0 + kSecond * (beat + 1);
    engine.onHeard(at);
    const ClientActions out = engine.tick(at, receiver.sampler());
    EXPECT_EQ(sent<Heartbeat>(out), std::vector<Heartbeat>{{beat}});
    EXPECT_EQ(sent<StatsReport>(out).size(), 1u);
    EXPECT_EQ(engine.nextWakeUp(), at + kSecond);
    EXPECT_TRUE(engine.tick(at + Micros{500'000}, receiver.sampler()).empty()) << "once per second";
  }
  EXPECT_EQ(receiver.calls, 3) << "the receiver is sampled once per report (a new loss interval each)";
}

TEST(ClientEngineCadence, StatsReportCarriesTheFiguresAsFiniteNonNegatives) {
  ClientEngine engine(config("a"));
  joinSession(engine, kT0);
  engine.onLevelDecoded(decodedLevel());
  engine.setDistortion(0.25, std::numeric_limits<double>::infinity(), 0.125);
  FakeReceiver receiver;
  const std::vector<StatsReport> stats = sent<StatsReport>(engine.tick(kT0 + kSecond, receiver.sampler()));
  ASSERT_EQ(stats.size(), 1u);
  const StatsReport& s = stats[0];
  EXPECT_EQ(s.vertexCount, 3u) << "the displayed level's";
  EXPECT_EQ(s.framesApplied, 30u);
  EXPECT_EQ(s.received, 40u);
  EXPECT_EQ(s.lost, 2u);
  EXPECT_EQ(s.dropped, 4u);
  EXPECT_EQ(s.jitterMs, 1.5);
  EXPECT_EQ(s.lossFraction, 0.0) << "NaN is sent as 0";
  EXPECT_EQ(s.latencyP50Ms, 0.0) << "negative is sent as 0";
  EXPECT_EQ(s.latencyP99Ms, 1.25) << "the last 10 s, not the whole run";
  EXPECT_EQ(s.hdMaxPct, 0.25);
  EXPECT_EQ(s.hdMeanPct, 0.0) << "infinity is sent as 0";
  EXPECT_EQ(s.hdLastPct, 0.125);
}

TEST(ClientEngineCadence, ASilentHostFailsAtTheFirstSecondTickPastTheTimeout) {
  ClientEngine engine(config("a", 0, std::nullopt, Millis{3000}));
  joinSession(engine, kT0);
  FakeReceiver receiver;
  for (int s = 1; s <= 3; ++s) {
    const ClientActions out = engine.tick(kT0 + kSecond * s, receiver.sampler());
    EXPECT_EQ(sent<Heartbeat>(out).size(), 1u) << "silent for " << s << " s: not yet";
  }
  const ClientActions out = engine.tick(kT0 + kSecond * 4, receiver.sampler());
  EXPECT_EQ(engine.state(), ClientState::Failed);
  EXPECT_EQ(engine.errorText(), QStringLiteral("host lost: not responding for 3 s"));
  EXPECT_TRUE(sentMessages(out).empty()) << "no heartbeat to a lost host";
  EXPECT_EQ(actionsOf<client_action::Failed>(out).size(), 1u);
  EXPECT_EQ(engine.nextWakeUp(), std::nullopt) << "no cadence once failed";
}

TEST(ClientEngineCadence, BytesFromTheHostKeepTheSessionAlive) {
  ClientEngine engine(config("a", 0, std::nullopt, Millis{3000}));
  joinSession(engine, kT0);
  FakeReceiver receiver;
  for (int s = 1; s <= 10; ++s) {
    engine.onHeard(kT0 + kSecond * s - Micros{200'000});
    engine.tick(kT0 + kSecond * s, receiver.sampler());
  }
  EXPECT_EQ(engine.state(), ClientState::Loading);
  EXPECT_EQ(receiver.calls, 10);
}

TEST(ClientEngineCadence, TheHeldLockIsRenewedWhenDue) {
  ClientEngine engine(config("a"));
  joinSession(engine, kT0);
  FakeReceiver receiver;
  engine.requestLock(kT0);
  const Micros granted = kT0 + Micros{100'000};
  engine.onMessage(message(LockNotice{LockNoticeKind::Granted, kSelf, 5}), granted);
  const Micros due = granted + kLockRenewEvery;
  EXPECT_EQ(engine.nextWakeUp(), kT0 + kSecond) << "the second tick comes first";
  engine.onHeard(kT0 + kSecond);
  EXPECT_TRUE(sent<LockMessage>(engine.tick(kT0 + kSecond, receiver.sampler())).empty()) << "renew not yet due";
  EXPECT_EQ(engine.nextWakeUp(), due);
  const ClientActions out = engine.tick(due, receiver.sampler());
  EXPECT_EQ(sent<LockMessage>(out), (std::vector<LockMessage>{{LockRequestKind::Renew, 5}}));
  EXPECT_TRUE(sent<Heartbeat>(out).empty());
  EXPECT_EQ(engine.nextWakeUp(), kT0 + 2 * kSecond);
  EXPECT_EQ(engine.lock()->nextRenewDue(), std::chrono::duration_cast<Millis>(due) + kLockRenewEvery);
  engine.releaseLock(due);
  EXPECT_EQ(engine.lock()->nextRenewDue(), std::nullopt);
  EXPECT_TRUE(sent<LockMessage>(engine.tick(due + kLockRenewEvery, receiver.sampler())).empty()) << "released";
}

TEST(ClientEngineCadence, AStallDoesNotBurstCatchUpHeartbeats) {
  ClientEngine engine(config("a"));
  joinSession(engine, kT0);
  FakeReceiver receiver;
  const Micros late = kT0 + kSecond * 5 + Micros{300'000};
  engine.onHeard(late);
  EXPECT_EQ(sent<Heartbeat>(engine.tick(late, receiver.sampler())).size(), 1u);
  EXPECT_EQ(engine.nextWakeUp(), late + kSecond);
}

}  // namespace
}  // namespace sc::session::test
