// Tests for src/session/engine/host_engine_frames.cpp and the drag path of host_engine_lock.cpp: drag coalescing,
// the still frame, the idle refresh and the Keyframe cadence, with a fake clock and no sockets.
#include "host_engine_fixture.h"

namespace sc::session::testing {
namespace {

using HostEngineFrames = HostEngineTest;

TEST_F(HostEngineFrames, CoalescesDragsCloserThanTheSpacing) {
  startEngine();  // coalesce = 8 ms
  holdLockWithCap();
  const Micros first = now();
  const std::vector<SendFrame> immediate = actionsOf<SendFrame>(lift(0.1));
  ASSERT_EQ(immediate.size(), 1u) << "the first drag solves and sends at once";
  EXPECT_EQ(immediate[0].frame, 1u);
  EXPECT_EQ(immediate[0].stamp, first) << "stamped with the drag's arrival";
  EXPECT_FALSE(immediate[0].still);

  advance(2ms);
  EXPECT_TRUE(actionsOf<SendFrame>(lift(0.2)).empty()) << "2 ms after a drag frame: held back";
  EXPECT_EQ(engine().nextWakeUp(), first + 8ms) << "the held pose goes out when the spacing has passed";
  advance(2ms);
  const Micros latest = now();
  EXPECT_TRUE(actionsOf<SendFrame>(lift(0.3)).empty());
  EXPECT_EQ(engine().counters().dragsAccepted, 3u);

  const std::vector<SendFrame> coalesced = actionsOf<SendFrame>(tickUntil(first + 8ms));
  ASSERT_EQ(coalesced.size(), 1u) << "two drags, one frame";
  EXPECT_EQ(coalesced[0].frame, 2u);
  EXPECT_EQ(coalesced[0].stamp, latest) << "the latest pose's arrival";
  EXPECT_FALSE(coalesced[0].Z->isApprox(*immediate[0].Z)) << "the latest pose was solved";
  EXPECT_EQ(engine().counters().framesSent, 2u);
}

TEST_F(HostEngineFrames, SpacingCountsFromDragFramesOnly) {
  HostEngineOptions options;
  options.coalesce = 200ms;
  startEngine(options);
  holdLockWithCap();
  const Micros dragFrame = now();
  ASSERT_EQ(actionsOf<SendFrame>(lift(0.1)).size(), 1u);
  const std::vector<SendFrame> still = actionsOf<SendFrame>(tickFor(120ms));
  ASSERT_EQ(still.size(), 1u);
  EXPECT_TRUE(still[0].still) << "the still frame (100 ms before any interval sample)";
  advance(30ms);
  EXPECT_TRUE(actionsOf<SendFrame>(lift(0.2)).empty()) << "150 ms after the drag frame: within 200 ms";
  EXPECT_EQ(engine().nextWakeUp(), dragFrame + 200ms) << "counted from the drag frame, not the still frame";
}

TEST_F(HostEngineFrames, OneStillFrameAfterTheLastMovingFrame) {
  startEngine();
  holdLockWithCap();
  for (int step = 1; step <= 6; ++step) {
    if (step > 1) {
      EXPECT_TRUE(actionsOf<SendFrame>(tickFor(50ms)).empty()) << "no still frame in mid-drag";
    }
    ASSERT_EQ(actionsOf<SendFrame>(lift(0.05 * step)).size(), 1u);
  }
  const std::shared_ptr<const Eigen::MatrixXd> lastZ = std::make_shared<Eigen::MatrixXd>(engine().coefficients());
  const std::uint32_t lastFrame = engine().currentFrame();
  // 50 ms drag spacing: due 1.25 × 50 = 62.5 ms after the last moving frame (a 1 ms timer grain: 63 ms).
  EXPECT_TRUE(actionsOf<SendFrame>(tickFor(62ms)).empty());
  const std::vector<SendFrame> still = actionsOf<SendFrame>(tickFor(1ms));
  ASSERT_EQ(still.size(), 1u);
  EXPECT_TRUE(still[0].still);
  EXPECT_EQ(still[0].frame, lastFrame + 1) << "a new frame number";
  EXPECT_EQ(*still[0].Z, *lastZ) << "the same Z";
  EXPECT_EQ(engine().counters().stillFramesSent, 1u);
  EXPECT_TRUE(actionsOf<SendFrame>(tickFor(800ms)).empty()) << "one still frame only; then the idle refresh";
}

TEST_F(HostEngineFrames, NoStillFrameWhenSwitchedOff) {
  HostEngineOptions options;
  options.stillFrame = false;
  startEngine(options);
  holdLockWithCap();
  ASSERT_EQ(actionsOf<SendFrame>(lift(0.1)).size(), 1u);
  EXPECT_TRUE(actionsOf<SendFrame>(tickFor(500ms)).empty());
  EXPECT_EQ(engine().counters().stillFramesSent, 0u);
}

TEST_F(HostEngineFrames, IdleRefreshRepeatsZEveryIdlePeriod) {
  startEngine();  // idleRefresh = 1000 ms, checked every 100 ms
  const Micros started = now();
  EXPECT_TRUE(actionsOf<SendFrame>(tickUntil(started + 999ms)).empty());
  const std::vector<SendFrame> first = actionsOf<SendFrame>(tickUntil(started + 1000ms));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].frame, 1u);
  EXPECT_EQ(first[0].stamp, started + 1000ms) << "stamped with the send time";
  EXPECT_FALSE(first[0].still);
  EXPECT_TRUE(first[0].Z->isZero()) << "nothing moved: the rest pose";
  const std::vector<SendFrame> later = actionsOf<SendFrame>(tickUntil(started + 3000ms));
  ASSERT_EQ(later.size(), 2u);
  EXPECT_EQ(later[0].stamp, started + 2000ms);
  EXPECT_EQ(later[1].stamp, started + 3000ms);
}

TEST_F(HostEngineFrames, DragFrameDelaysTheIdleRefresh) {
  HostEngineOptions options;
  options.stillFrame = false;
  startEngine(options);
  holdLockWithCap();
  tickFor(500ms);
  const Micros dragged = now();
  ASSERT_EQ(actionsOf<SendFrame>(lift(0.1)).size(), 1u);
  EXPECT_TRUE(actionsOf<SendFrame>(tickUntil(dragged + 900ms)).empty()) << "idle counts from the last frame";
  EXPECT_EQ(actionsOf<SendFrame>(tickUntil(dragged + 1000ms)).size(), 1u);
}

TEST_F(HostEngineFrames, KeyframeEveryReferenceEveryFramesToLoadedPeersOnly) {
  HostEngineOptions options;
  options.referenceEvery = 3;
  startEngine(options);
  const PeerId loaded = join(QStringLiteral("loaded"));
  const PeerId empty = join(QStringLiteral("empty"));
  engine().onMessage(loaded, ResolutionRequest{0}, now());
  engine().onLevelReady(static_cast<std::uint32_t>(s_model->vertexCount()),
                        {static_cast<std::uint32_t>(s_model->vertexCount()), 320, 4000}, now());
  ASSERT_EQ(sentTo<Keyframe>(engine().onTransferFinished(loaded, now()), loaded).size(), 1u);
  const std::uint64_t keyframesAtLoad = engine().counters().keyframesSent;

  holdLockWithCap();
  HostActions frames;
  for (int step = 1; step <= 6; ++step) {
    advance(50ms);
    HostActions stepActions = lift(0.05 * step);
    frames.list.insert(frames.list.end(), stepActions.list.begin(), stepActions.list.end());
  }
  const std::vector<Keyframe> keyframes = sentTo<Keyframe>(frames, loaded);
  ASSERT_EQ(keyframes.size(), 2u) << "frames 3 and 6";
  EXPECT_EQ(keyframes[0].frame, 3u);
  EXPECT_EQ(keyframes[1].frame, 6u);
  ASSERT_EQ(keyframes[1].z.size(), static_cast<std::size_t>(3 * s_model->rowCount()));
  EXPECT_DOUBLE_EQ(keyframes[1].z[3 * 2 + 1], engine().coefficients()(2, 1)) << "Z row-major";
  EXPECT_TRUE(sentTo<Keyframe>(frames, empty).empty()) << "a peer without a model gets none";
  EXPECT_EQ(engine().counters().keyframesSent, keyframesAtLoad + 2);
}

TEST_F(HostEngineFrames, NoKeyframesWhenReferenceEveryIsZero) {
  HostEngineOptions options;
  options.referenceEvery = 0;
  startEngine(options);
  const PeerId peer = join(QStringLiteral("peer"));
  engine().onMessage(peer, ResolutionRequest{0}, now());
  engine().onLevelReady(static_cast<std::uint32_t>(s_model->vertexCount()),
                        {static_cast<std::uint32_t>(s_model->vertexCount()), 320, 4000}, now());
  engine().onTransferFinished(peer, now());
  EXPECT_TRUE(sentTo<Keyframe>(tickFor(5s), peer).empty()) << "five idle refreshes, no Keyframe";
}

}  // namespace
}  // namespace sc::session::testing
