// The relay through a real nats-server (issue 18, acceptance): a host and 8 viewers receive every frame in order; a
// late joiner starts from the keyframe; a viewer's publish on the frame subject is refused by the server; a viewer
// that stops reading loses frames while the others lose none; viewers resume within 2 s of a server restart on the
// same port; a frame with a bad signature is dropped and counted; the viewers' figures reach the host as one
// aggregate; a viewer that misses frames measures distortion against the keyframes read back, one that gets them all
// measures none; an extrapolating viewer predicts the frames it misses. Fixture: relay_nats_fixture.h.
#include "relay_nats_fixture.h"

#include "session/wire/relay_message.h"

#include <cstdio>

namespace sc::session {
namespace {

TEST_F(RelayNats, AHostAndEightViewersReceiveEveryFrameInOrder) {
  for (int i = 0; i < 8; ++i) ASSERT_NE(addViewer(), nullptr);
  std::vector<RelayViewerStats> before;
  for (const auto& viewer : m_viewers) before.push_back(viewer->stats());
  const std::uint32_t first = m_host->currentFrame();
  for (int step = 1; step <= 20; ++step) dragOnce(0.01 * step);
  ASSERT_GE(m_host->currentFrame(), first + 20);
  ASSERT_TRUE(waitFor([&] {
    return std::all_of(m_viewers.begin(), m_viewers.end(), [&](const auto& viewer) { return caughtUp(*viewer); });
  }));
  for (std::size_t i = 0; i < m_viewers.size(); ++i) {
    const RelayViewer& viewer = *m_viewers[i];
    const RelayViewerStats stats = viewer.stats();
    EXPECT_EQ(stats.lost - before[i].lost, 0) << i;    // none skipped
    EXPECT_EQ(stats.stale - before[i].stale, 0) << i;  // none out of order or repeated
    EXPECT_GE(stats.applied - before[i].applied, 20) << i;
    EXPECT_EQ(stats.badSignature + stats.malformed, 0) << i;
    EXPECT_EQ(viewer.droppedPending(), 0) << i;
    EXPECT_EQ(viewer.receiver().coefficients(), m_host->coefficients()) << i;  // exact
  }
  // One publish per frame whatever the number of viewers.
  EXPECT_GE(m_publisher->counters().frames, 20);
  EXPECT_EQ(m_publisher->counters().failures, 0);
}

TEST_F(RelayNats, ALateJoinerStartsFromTheKeyframe) {
  for (int step = 1; step <= 10; ++step) dragOnce(0.02 * step);
  QTest::qWait(400);  // the trailing keyframe is stored 200 ms after the last frame
  const std::uint32_t last = m_host->currentFrame();
  RelayViewer* late = addViewer();
  ASSERT_NE(late, nullptr);
  ASSERT_TRUE(late->receiver().frame());  // joined from the keyframe, before any new frame
  EXPECT_GE(*late->receiver().frame(), last);
  EXPECT_EQ(late->receiver().coefficients(), m_host->coefficients());
  EXPECT_FALSE(late->receiver().coefficients().isZero());
  dragOnce(0.5);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*late); }));
  EXPECT_EQ(late->receiver().coefficients(), m_host->coefficients());
  EXPECT_EQ(late->stats().lost, 0);
}

TEST_F(RelayNats, AViewersPublishOnTheFrameSubjectIsRefused) {
  RelayViewer* viewer = addViewer();
  ASSERT_NE(viewer, nullptr);
  QString why;
  std::unique_ptr<NatsConnection> rogue = NatsConnection::connect(viewerCredential(), &why);
  ASSERT_TRUE(rogue) << why.toStdString();
  RelayFrame frame;
  frame.frame = m_host->currentFrame() + 1;
  frame.Z = Eigen::MatrixXd::Constant(s_model->rowCount(), 3, 0.3);
  const TlsIdentity other = *generateTlsIdentity(QStringLiteral("rogue"));
  const QByteArray forged =
      RelaySigner(other.privateKey.toDer(), m_server.config().sessionId).sign(encodeRelayFrameBody(frame));
  rogue->publish(m_publisher->frameSubject(), forged);
  rogue->flush(std::chrono::milliseconds(2000));
  ASSERT_TRUE(waitFor([&] { return rogue->lastError().contains(QStringLiteral("Permissions Violation")); }))
      << rogue->lastError().toStdString();
  rogue->publish(natsKeySubject(relayBucket(m_server.config().sessionId), "keyframe"), forged);
  QTest::qWait(300);
  const RelayViewerStats stats = viewer->stats();
  EXPECT_EQ(stats.badSignature + stats.malformed, 0);  // nothing reached the viewer
  EXPECT_NE(viewer->receiver().frame(), frame.frame);
}

TEST_F(RelayNats, AViewerThatStopsReadingLosesFramesWhileTheOthersLoseNone) {
  RelayViewer* stalled = addViewer(/*pendingLimit=*/4);
  RelayViewer* a = addViewer();
  RelayViewer* b = addViewer();
  ASSERT_TRUE(stalled && a && b);
  dragOnce(0.005);  // every viewer sees a live frame first: loss counts from there
  ASSERT_TRUE(waitFor([&] { return caughtUp(*stalled) && caughtUp(*a) && caughtUp(*b); }));
  const std::int64_t lostBefore = a->stats().lost + b->stats().lost;
  stalled->setPaused(true);
  for (int step = 1; step <= 30; ++step) dragOnce(0.01 * step);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*a) && caughtUp(*b); }));
  EXPECT_EQ(a->stats().lost + b->stats().lost - lostBefore, 0);
  EXPECT_EQ(a->droppedPending() + b->droppedPending(), 0);
  EXPECT_GE(stalled->droppedPending(), 30 - 4);  // only the newest 4 waited
  stalled->setPaused(false);                     // reads again: the newest frame wins
  ASSERT_TRUE(waitFor([&] { return caughtUp(*stalled); }));
  EXPECT_GE(stalled->stats().lost, 30 - 4);
  EXPECT_EQ(stalled->receiver().coefficients(), m_host->coefficients());
}

TEST_F(RelayNats, AViewerThatMissesFramesReportsDistortionWhileAViewerThatGetsThemAllReportsNone) {
  RelayViewer* stalled = addViewer(/*pendingLimit=*/4);
  RelayViewer* normal = addViewer();
  ASSERT_TRUE(stalled && normal);
  const spectral::SharedDisplayLevel level = fullLevel();
  stalled->setLevel(level);
  normal->setLevel(level);
  dragOnce(0.005);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*stalled) && caughtUp(*normal); }));
  // The stalled viewer keeps an old shape on screen while the host stores keyframes (every 30 frames) that both
  // viewers read back as exact references.
  stalled->setPaused(true);
  for (int step = 1; step <= 45; ++step) dragOnce(0.01 * step);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*normal); }));
  stalled->setPaused(false);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*stalled); }));
  ASSERT_TRUE(waitFor([&] {
    return stalled->display().distortion().maxPct > 0.0 && normal->display().distortion().count >= 2;
  })) << "stalled: "
      << stalled->display().distortion().count << " measured, " << stalled->display().counts().references
      << " references; normal: " << normal->display().distortion().count;
  EXPECT_GT(stalled->display().distortion().maxPct, 0.01);  // % of the diagonal: the cap moved by up to 0.45
  EXPECT_EQ(normal->display().distortion().maxPct, 0.0);    // every frame arrived, exact: nothing to conceal
  EXPECT_GE(stalled->stats().lost, 30);
  // Both figures reach the host's aggregate.
  ASSERT_TRUE(waitFor([&] {
    const RelayAudienceSummary audience = m_publisher->audience();
    return audience.distortionViewers == 2 && audience.distortionMaxPct.max > 0.01;
  }));
  EXPECT_EQ(m_publisher->audience().distortionMaxPct.min, 0.0);
}

TEST_F(RelayNats, AnExtrapolatingViewerPredictsTheFramesItMissesThenShowsTheRelayedShape) {
  RelayViewer* viewer = addViewer(8, Concealment::Extrapolate);
  ASSERT_NE(viewer, nullptr);
  // It stops reading in mid-drag: the frames it expects are overdue, so it predicts them (at most 4), then withdraws
  // the prediction and holds the last frame it got.
  for (int step = 1; step <= 20; ++step) {
    if (step == 10) viewer->setPaused(true);
    dragOnce(0.01 * step);
  }
  ASSERT_TRUE(waitFor([&] { return viewer->display().counts().withdrawn >= 1; }));
  EXPECT_GE(viewer->display().counts().predicted, 1u);
  EXPECT_EQ(viewer->display().display(), viewer->receiver().coefficients());
  viewer->setPaused(false);  // reads again: the newest relayed frame replaces whatever was shown
  ASSERT_TRUE(waitFor([&] { return caughtUp(*viewer); }));
  ASSERT_TRUE(waitFor([&] { return viewer->display().displayedFrame() == m_host->currentFrame(); }));
  EXPECT_EQ(viewer->display().display(), m_host->coefficients());
}

TEST_F(RelayNats, ViewersResumeWithinTwoSecondsOfAServerRestartOnTheSamePort) {
  for (int i = 0; i < 4; ++i) ASSERT_NE(addViewer(), nullptr);
  dragOnce(0.1);
  ASSERT_TRUE(waitFor([&] {
    return std::all_of(m_viewers.begin(), m_viewers.end(), [&](const auto& viewer) { return caughtUp(*viewer); });
  }));
  const int port = m_server.port();
  const std::uint32_t before = m_host->currentFrame();
  QString error;
  ASSERT_TRUE(m_server.restart(&error)) << error.toStdString();
  ASSERT_EQ(m_server.port(), port);
  QElapsedTimer clock;
  clock.start();
  double dz = 0.1;
  auto resumed = [&] {
    return std::all_of(m_viewers.begin(), m_viewers.end(), [&](const auto& viewer) {
      return viewer->receiver().frame() && static_cast<std::int32_t>(*viewer->receiver().frame() - before) > 0;
    });
  };
  while (!resumed() && clock.elapsed() < 4000) dragOnce(dz += 0.01);  // the host keeps editing
  const qint64 elapsed = clock.elapsed();
  std::printf("[ relay ] viewers resumed %lld ms after the server restarted\n", static_cast<long long>(elapsed));
  EXPECT_TRUE(resumed());
  EXPECT_LT(elapsed, 2000);
  for (const auto& viewer : m_viewers) EXPECT_GE(viewer->connection()->reconnections(), 1);
}

TEST_F(RelayNats, AFrameWithABadSignatureIsDroppedAndCounted) {
  RelayViewer* viewer = addViewer();
  ASSERT_NE(viewer, nullptr);
  dragOnce(0.1);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*viewer); }));
  const Eigen::MatrixXd shape = viewer->receiver().coefficients();
  // What a compromised broker (or a leaked host password) can send: well-formed, signed by another key.
  NatsConnectOptions hostCredential = viewerCredential();
  hostCredential.user = m_server.config().hostUser;
  hostCredential.password = m_server.config().hostPassword;
  QString why;
  std::unique_ptr<NatsConnection> broker = NatsConnection::connect(hostCredential, &why);
  ASSERT_TRUE(broker) << why.toStdString();
  RelayFrame frame;
  frame.frame = m_host->currentFrame() + 1000;
  frame.Z = Eigen::MatrixXd::Constant(s_model->rowCount(), 3, 0.3);
  const TlsIdentity other = *generateTlsIdentity(QStringLiteral("forger"));
  ASSERT_TRUE(broker->publish(
      m_publisher->frameSubject(),
      RelaySigner(other.privateKey.toDer(), m_server.config().sessionId).sign(encodeRelayFrameBody(frame))));
  ASSERT_TRUE(broker->flush(std::chrono::milliseconds(2000)));
  ASSERT_TRUE(waitFor([&] { return viewer->stats().badSignature == 1; }));
  EXPECT_EQ(viewer->receiver().coefficients(), shape);  // unchanged
  dragOnce(0.2);
  ASSERT_TRUE(waitFor([&] { return caughtUp(*viewer); }));  // the host's frames still apply
  EXPECT_EQ(viewer->stats().badSignature, 1);
}

TEST_F(RelayNats, TheViewersFiguresReachTheHostAsOneAggregate) {
  for (int i = 0; i < 3; ++i) ASSERT_NE(addViewer(), nullptr);
  for (int step = 1; step <= 5; ++step) dragOnce(0.01 * step);
  ASSERT_TRUE(waitFor([&] {
    const RelayAudienceSummary a = m_publisher->audience();
    return a.viewers == 3 && a.latencyP99Ms.min > 0.0;
  }));
  const RelayAudienceSummary a = m_publisher->audience();
  EXPECT_EQ(a.lossFraction.max, 0.0);
  EXPECT_EQ(a.badSignature, 0);
  EXPECT_EQ(a.malformed, 0);
}

}  // namespace
}  // namespace sc::session
