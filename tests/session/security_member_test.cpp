// A hostile member (docs/security.md, "Hostile member"): one that joins, takes the lock, stops reading and sends
// resolution and lock requests is dropped within seconds, whether it stays under the message rate (its queue
// reaches the send budget, which the host's queue for it never passes) or floods (over the message rate); its lock
// is freed and an honest client keeps receiving frames. Real TLS over loopback sockets. Fixture: security_fixture.h.
#include "security_fixture.h"

#include "model/decimating_level_builder.h"
#include "raw_control_peer.h"

#include <QtCore/QElapsedTimer>
#include <QtTest/QTest>

namespace sc::session {
namespace {

class HostileMember : public Security {
 protected:
  /// Host options with a ladder of levels (alternating requests each start a transfer) and, when `throttled` is false,
  /// the message and request rates off, so that the requests make the host send as much as they can.
  static SessionHostOptions memberHostOptions(bool throttled) {
    SessionHostOptions options = hostOptions(std::nullopt);
    options.levelBuilder = LevelBuilder{model::levelTargetList, model::decimatedLevel};
    if (!throttled) {
      options.messageRate = RateLimit{};
      options.lockRequestRate = RateLimit{};
      options.resolutionRequestRate = RateLimit{};
    }
    return options;
  }

  /// Starts a host with `options`, an honest client, and a raw member (4 KiB receive buffer) that takes the lock
  /// and stops reading.
  void startSession(SessionHostOptions options) {
    m_host = startHost(options);
    m_honest = start(clientOptions(m_host->tcpPort(), QStringLiteral("honest"), std::nullopt));
    ASSERT_TRUE(settle(*m_honest)) << m_honest->errorText().toStdString();
    m_member = std::make_unique<testing::RawControlPeer>(m_host->tcpPort(), 4096);
    const std::optional<Welcome> welcome = m_member->join(QStringLiteral("hog"));
    ASSERT_TRUE(welcome);
    m_memberId = welcome->peerId;
    ASSERT_NE(m_member->acquireLock(m_memberId), kNoEpoch);
    ASSERT_EQ(m_host->lockHolder(), m_memberId);
    m_member->stopReading();
  }

  /// Sends `perBurst` alternating resolution requests and lock re-requests every `everyMs` until the host drops
  /// the member (or kRawWaitMs); returns how long that took. Checks that the honest client received frames
  /// meanwhile when `framesDuring` (refresh frames at 10 Hz, the housekeeping period: at least half of them; the
  /// fastest flood is written by this very process, which then has no time left for the honest client) and that it
  /// receives frames afterwards.
  qint64 floodUntilDropped(int perBurst, int everyMs, bool framesDuring) {
    const std::uint64_t appliedBefore = m_honest->channel().framesApplied();
    QElapsedTimer clock;
    clock.start();
    bool dropped = false;
    for (int round = 0; !dropped && clock.elapsed() < testing::kRawWaitMs; ++round) {
      for (int i = 0; i < perBurst; ++i) {
        m_member->send(ResolutionRequest{(round + i) % 2 == 0 ? 0u : 40u});
        m_member->send(LockMessage{LockRequestKind::Request, kNoEpoch});
      }
      QTest::qWait(everyMs);
      dropped = members(*m_host) == 1;
    }
    const qint64 elapsedMs = clock.elapsed();
    EXPECT_TRUE(dropped) << "the member is still there after " << elapsedMs << " ms";
    EXPECT_EQ(m_host->lockHolder(), kNoPeer) << "the member's lock is freed";
    if (framesDuring) {
      EXPECT_GT(m_honest->channel().framesApplied(), appliedBefore + static_cast<std::uint64_t>(elapsedMs / 200));
    }
    const std::uint64_t after = m_honest->channel().framesApplied();
    EXPECT_TRUE(QTest::qWaitFor([&] { return m_honest->channel().framesApplied() > after + 5; }, kWaitMs));
    EXPECT_EQ(m_honest->state(), SessionClient::State::Ready);
    return elapsedMs;
  }

  std::unique_ptr<SessionHost> m_host;
  std::unique_ptr<SessionClient> m_honest;
  std::unique_ptr<testing::RawControlPeer> m_member;
  PeerId m_memberId = kNoPeer;
};

TEST_F(HostileMember, MemberThatNeverReadsIsDroppedAtTheSendBudget) {
  SessionHostOptions options = memberHostOptions(false);
  options.sendBudgetBytes = 128 * 1024;
  options.sendStallTimeout = std::chrono::milliseconds(10000);  // the budget, not the stall, must catch it
  ASSERT_NO_FATAL_FAILURE(startSession(options));
  const qint64 elapsedMs = floodUntilDropped(20, 20, true);  // 2,000 messages/s
  EXPECT_LT(elapsedMs, 4000);
  EXPECT_EQ(m_host->counters().slowPeersDropped, 1u);
  EXPECT_GT(m_host->counters().peakSendQueueBytes, 0);
  EXPECT_LE(m_host->counters().peakSendQueueBytes, options.sendBudgetBytes) << "never more queued than the budget";
}

TEST_F(HostileMember, MemberThatNeverReadsAndFloodsIsDroppedAtTheMessageRate) {
  ASSERT_NO_FATAL_FAILURE(startSession(memberHostOptions(true)));
  const qint64 elapsedMs = floodUntilDropped(100, 5, false);  // 40,000 messages/s
  EXPECT_LT(elapsedMs, 2000);
  EXPECT_EQ(m_host->counters().floodingPeersDropped, 1u);
  EXPECT_GT(m_host->counters().requestsThrottled, 0u);
  EXPECT_LE(m_host->counters().peakSendQueueBytes, m_host->options().sendBudgetBytes);
}

}  // namespace
}  // namespace sc::session
