// Loopback tests of the deformation reaching the clients (src/session/net/session_host.cpp, session_client.cpp and the
// datagram channels): a late joiner gets the current Z at once in its keyframe, a holder's drag produces frames at
// the other clients within quantisation, and Z changes within one event-loop pass are reconstructed once. Real
// sockets on 127.0.0.1. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include "session/net/client_datagram_channel.h"
#include "session/net/host_datagram_channel.h"
#include "spectral/resolution_level.h"

#include <QtTest/QTest>

#include <algorithm>
#include <cmath>

namespace sc::session {
namespace {

TEST_F(SessionLoopback, LateJoinGetsTheCurrentDeformationAtOnce) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);  // no refresh frames: the keyframe alone must carry Z
  auto host = startHost(options);
  // The still frame after the drag (same Z) goes out before the late join: no datagram frame follows the join.
  ASSERT_NO_FATAL_FAILURE(liftTheCapAndWaitForTheStillFrame(*host));
  const Eigen::MatrixXd expected = host->coefficients();

  std::optional<std::pair<std::uint32_t, Eigen::MatrixXd>> keyframe;
  auto late = connectClient(*host, QStringLiteral("late"));
  QObject::connect(late.get(), &SessionClient::keyframeReceived, late.get(),
                   [&](std::uint32_t frame, const Eigen::MatrixXd& Z) {
                     if (!keyframe) keyframe.emplace(frame, Z);
                   });
  ASSERT_TRUE(waitReady(*late)) << late->errorText().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return keyframe.has_value(); }, kWaitMs));
  EXPECT_EQ(keyframe->first, host->currentFrame());
  EXPECT_EQ(keyframe->second, expected);  // exact: float64 on the wire
  EXPECT_EQ(late->channel().coefficients(), expected);
  // The displayed positions are the deformed shape: the cap moved up by about the drag. The keyframe may come in
  // after the level was installed: its recompute is then coalesced into the next event-loop pass.
  const std::uint32_t handleTop = capConstraints().first.front();
  const auto top = static_cast<std::size_t>(handleTop);
  ASSERT_TRUE(QTest::qWaitFor([&] { return late->positionsFrame() == keyframe->first; }, kWaitMs));
  EXPECT_GT(late->positions()[3 * top + 2], static_cast<float>(s_model->V(handleTop, 2)) + 0.2f);
  // The lock holder is announced to the newcomer.
  ASSERT_TRUE(QTest::qWaitFor([&] { return late->lock()->holder() == kHostPeer; }, kWaitMs));
}

TEST_F(SessionLoopback, DragByTheHolderProducesFramesAtTheOtherClients) {
  SessionHostOptions options = hostOptions();
  options.referenceEvery = 5;
  auto host = startHost(options);
  auto dragger = join(*host, QStringLiteral("dragger"));
  auto viewer = join(*host, QStringLiteral("viewer"), 30);
  ASSERT_TRUE(dragger->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return dragger->lock()->canDrag(); }, kWaitMs));
  EXPECT_FALSE(viewer->sendDrag({lift(0.3)}));  // refused locally without the lock
  const auto [handle, anchors] = capConstraints();
  ASSERT_TRUE(dragger->sendConstraints({handle}, anchors));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kWaitMs));

  const std::uint64_t appliedBefore = viewer->channel().framesApplied();
  std::uint64_t keyframesBefore = viewer->keyframesReceived();
  for (int step = 1; step <= 20; ++step) {
    ASSERT_TRUE(dragger->sendDrag({lift(0.02 * step)}));
    QTest::qWait(15);
  }
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().dragsAccepted == 20; }, kWaitMs));
  ASSERT_TRUE(QTest::qWaitFor([&] { return viewer->channel().currentFrame() == host->currentFrame(); }, kWaitMs));
  EXPECT_GT(viewer->channel().framesApplied(), appliedBefore + 5);
  EXPECT_GT(viewer->keyframesReceived(), keyframesBefore);  // references every 5 frames
  // Quantised int16 per band: within a small fraction of the largest coefficient.
  const Eigen::MatrixXd& Z = host->coefficients();
  EXPECT_LT((viewer->channel().coefficients() - Z).cwiseAbs().maxCoeff(), 1e-3 * Z.cwiseAbs().maxCoeff());
  EXPECT_EQ(dragger->channel().currentFrame(), host->currentFrame());
  // Recomputes are coalesced (at most one per event-loop pass, never more than one per applied datagram plus the
  // level install) and follow the latest frame.
  ASSERT_TRUE(QTest::qWaitFor([&] { return viewer->positionsFrame() == host->currentFrame(); }, kWaitMs));
  EXPECT_LE(viewer->positionUpdates(), viewer->channel().framesApplied() + viewer->keyframesReceived() + 1);
  // The viewer's low-resolution positions moved: X' = X̂' + K·Z.
  const spectral::ResolutionLevel& level = *viewer->level();
  double maxMove = 0.0;
  for (Eigen::Index i = 0; i < level.restV.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      maxMove =
          std::max(maxMove, std::abs(viewer->positions()[static_cast<std::size_t>(3 * i + c)] - level.restV(i, c)));
    }
  }
  EXPECT_GT(maxMove, 0.2);
  // The viewer reports its statistics about once a second.
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->stats(viewer->peerId()).has_value(); }, 3000));
  EXPECT_EQ(host->stats(viewer->peerId())->vertexCount, viewer->levelVertexCount());
}

TEST_F(SessionLoopback, ZChangesWithinOneEventLoopPassAreReconstructedOnceAndWhenRead) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);  // no datagram frames: the seeds below stay applicable
  auto host = startHost(options);
  auto client = join(*host, QStringLiteral("coalesced"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return client->keyframesReceived() >= 1; }, kWaitMs));
  QTest::qWait(50);  // let a recompute scheduled by the join keyframe run
  const std::uint64_t before = client->positionUpdates();
  std::vector<std::uint32_t> emitted;
  QObject::connect(client.get(), &SessionClient::positionsUpdated, client.get(),
                   [&](std::uint32_t frame) { emitted.push_back(frame); });

  // Three Z changes back to back, as from three datagrams read in one pass: each emits frameUpdated at once ...
  const auto m = static_cast<Eigen::Index>(s_model->rowCount());
  int updatedSignals = 0;
  QObject::connect(&client->channel(), &ClientDatagramChannel::frameUpdated, client.get(), [&] { ++updatedSignals; });
  for (std::uint32_t frame = 1; frame <= 3; ++frame) {
    client->channel().seed(frame, Eigen::MatrixXd::Constant(m, 3, 0.01 * frame));
  }
  EXPECT_EQ(updatedSignals, 3);
  EXPECT_EQ(client->positionUpdates(), before);  // ... but nothing is reconstructed synchronously
  // ... and one recompute, of the latest Z, follows.
  ASSERT_TRUE(QTest::qWaitFor([&] { return client->positionUpdates() > before; }, kWaitMs));
  QTest::qWait(50);
  EXPECT_EQ(client->positionUpdates(), before + 1);
  EXPECT_EQ(emitted, (std::vector<std::uint32_t>{3}));
  EXPECT_EQ(client->positionsFrame(), 3u);
  EXPECT_EQ(client->positionsCoefficients(), Eigen::MatrixXf::Constant(m, 3, 0.03f));
  // positions() is reconstructed when first read, from the Z of positionsFrame(): a newer Z that arrived in the
  // meantime (its update not run yet) does not leak into it.
  client->channel().seed(4, Eigen::MatrixXd::Constant(m, 3, 0.5));
  const spectral::ResolutionLevel& level = *client->level();
  const Eigen::MatrixXd Z = Eigen::MatrixXd::Constant(m, 3, 0.03);
  for (const Eigen::Index i : {Eigen::Index{0}, level.restV.rows() / 2, level.restV.rows() - 1}) {
    for (int c = 0; c < 3; ++c) {
      const double expected = level.restV(i, c) + level.K.row(i).transpose().cast<double>().dot(Z.col(c));
      EXPECT_NEAR(client->positions()[static_cast<std::size_t>(3 * i + c)], expected, 1e-5);
    }
  }
}

}  // namespace
}  // namespace sc::session
