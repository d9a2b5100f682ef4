// Tests for the ClientEngine's level pipeline and frames (src/session/engine/client_engine_levels.cpp): one decode
// at a time, the latest completed transfer supersedes, results after leave or failure dropped, keyframes, and the
// coalescing of frame updates. A fake host and a fake decode worker (the test calls onLevelDecoded()).
#include "client_engine_fixture.h"

namespace sc::session::test {
namespace {

class ClientEngineLevels : public ::testing::Test {
 protected:
  void SetUp() override { joinSession(engine, kT0); }
  /// The job of the StartDecode among `out` (fails the test when there is none).
  static LevelJob startedJob(const ClientActions& out) {
    const auto started = actionsOf<client_action::StartDecode>(out);
    EXPECT_EQ(started.size(), 1u);
    return started.empty() ? LevelJob{} : started[0].job;
  }
  ClientEngine engine{config("levels")};
};

TEST_F(ClientEngineLevels, ACompletedTransferIsDecodedWithTheSessionsShape) {
  const QByteArray payload = tinyPayload("x");
  ClientActions out = deliverTransfer(engine, payload, 1, kT0, 64);
  const LevelJob job = startedJob(out);
  EXPECT_EQ(job.payload, payload);
  EXPECT_EQ(job.sha256, sha256(payload));
  EXPECT_EQ(job.rowCount, kRows);
  EXPECT_EQ(job.vertexCount, kVertices);
  const auto progress = actionsOf<client_action::ModelProgress>(out);
  ASSERT_EQ(progress.size(), 1u);
  EXPECT_EQ(progress[0].received, static_cast<std::uint32_t>(payload.size()));
  EXPECT_EQ(progress[0].total, static_cast<std::uint32_t>(payload.size()));
  EXPECT_TRUE(engine.levelDecoding());
  EXPECT_EQ(engine.state(), ClientState::Loading) << "until the decoded level is installed";
}

TEST_F(ClientEngineLevels, InstallingALevelPublishesItsFirstFrameThenReady) {
  startedJob(deliverTransfer(engine, tinyPayload("a"), 1, kT0));
  const ClientActions out = engine.onLevelDecoded(decodedLevel());
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(std::get<client_action::Notify>(out[0]).notice, ClientNotice::LevelInstalled);
  EXPECT_TRUE(std::holds_alternative<client_action::PublishFrame>(out[1]));
  EXPECT_EQ(std::get<client_action::StateChanged>(out[2]).state, ClientState::Ready);
  EXPECT_EQ(std::get<client_action::LevelReady>(out[3]).vertexCount, 3u);
  EXPECT_FALSE(engine.levelDecoding());
  EXPECT_TRUE(engine.levelPayload().isEmpty()) << "freed once decoded (it was kept for the session's life)";
  EXPECT_EQ(engine.framesPublished(), 1u);
}

TEST_F(ClientEngineLevels, TheInstalledPayloadIsKeptOnlyWhenAskedFor) {
  ClientEngineConfig keeping = config("keeper");
  keeping.keepLevelPayload = true;
  ClientEngine keeper(keeping);
  joinSession(keeper, kT0);
  startedJob(deliverTransfer(keeper, tinyPayload("a"), 1, kT0));
  (void)keeper.onLevelDecoded(decodedLevel());
  EXPECT_EQ(keeper.levelPayload(), QByteArray("payload"));
}

TEST_F(ClientEngineLevels, OneDecodeAtATimeAndTheLatestTransferSupersedes) {
  startedJob(deliverTransfer(engine, tinyPayload("first"), 1, kT0));
  EXPECT_TRUE(actionsOf<client_action::StartDecode>(deliverTransfer(engine, tinyPayload("second"), 2, kT0)).empty())
      << "waits for the running decode";
  EXPECT_TRUE(actionsOf<client_action::StartDecode>(deliverTransfer(engine, tinyPayload("third"), 3, kT0)).empty());
  // The first result comes back: dropped, superseded by the latest completed transfer (the second never runs).
  ClientActions out = engine.onLevelDecoded(decodedLevel(1.0f));
  EXPECT_EQ(startedJob(out).payload, tinyPayload("third"));
  EXPECT_TRUE(actionsOf<client_action::LevelReady>(out).empty());
  EXPECT_EQ(engine.displayLevel(), nullptr);
  EXPECT_TRUE(engine.levelDecoding());
  out = engine.onLevelDecoded(decodedLevel(2.0f));
  ASSERT_NE(engine.displayLevel(), nullptr);
  EXPECT_FLOAT_EQ(engine.displayLevel()->level.K(0, 0), 2.0f) << "the latest is installed";
  EXPECT_EQ(actionsOf<client_action::LevelReady>(out).size(), 1u);
}

TEST_F(ClientEngineLevels, ABadLevelIsReportedAndThePreviousOneStays) {
  startedJob(deliverTransfer(engine, tinyPayload("good"), 1, kT0));
  engine.onLevelDecoded(decodedLevel(1.0f));
  const spectral::SharedDisplayLevel shown = engine.displayLevel();
  startedJob(deliverTransfer(engine, tinyPayload("bad"), 2, kT0));
  const ClientActions out = engine.onLevelDecoded(DecodedLevel{{}, nullptr, QStringLiteral("bad level payload: x")});
  EXPECT_EQ(actionsOf<client_action::LevelFailed>(out).at(0).reason, QStringLiteral("bad level payload: x"));
  EXPECT_EQ(engine.levelError(), QStringLiteral("bad level payload: x"));
  EXPECT_EQ(engine.displayLevel(), shown);
  EXPECT_EQ(engine.state(), ClientState::Ready) << "the connection is kept";
}

TEST_F(ClientEngineLevels, ResultsAfterLeaveOrFailureAreDropped) {
  startedJob(deliverTransfer(engine, tinyPayload("a"), 1, kT0));
  engine.leave();
  EXPECT_TRUE(engine.onLevelDecoded(decodedLevel()).empty());
  EXPECT_EQ(engine.displayLevel(), nullptr);

  ClientEngine failing{config("f")};
  joinSession(failing, kT0);
  startedJob(deliverTransfer(failing, tinyPayload("a"), 1, kT0));
  deliverTransfer(failing, tinyPayload("b"), 2, kT0);
  failing.onClosed();
  EXPECT_TRUE(failing.onLevelDecoded(decodedLevel()).empty()) << "not even the waiting transfer starts";
  EXPECT_EQ(failing.displayLevel(), nullptr);
}

TEST_F(ClientEngineLevels, AnOutOfOrderChunkFailsTheTransferNotTheSession) {
  const QByteArray payload = tinyPayload("0123456789");
  const auto size = static_cast<std::uint32_t>(payload.size());
  engine.onMessage(message(tinyLevelList(size)), kT0);
  engine.onMessage(message(ModelBegin{1, TransferKind::Level, kVertices, size, sha256(payload)}), kT0);
  const ClientActions out = engine.onMessage(message(ModelChunk{1, 4, size, payload.mid(4)}), kT0);
  EXPECT_TRUE(
      actionsOf<client_action::LevelFailed>(out).at(0).reason.startsWith(QStringLiteral("model transfer failed")));
  EXPECT_EQ(engine.state(), ClientState::Loading);
}

TEST_F(ClientEngineLevels, KeyframesOfThisSessionsShapeAreSeeded) {
  EXPECT_TRUE(engine.onMessage(message(Keyframe{7, {1, 2, 3}}), kT0).empty()) << "m = 1 ≠ 2: ignored";
  const ClientActions out = engine.onMessage(message(Keyframe{8, {1, 2, 3, 4, 5, 6}}), kT0);
  const auto seeds = actionsOf<client_action::SeedKeyframe>(out);
  ASSERT_EQ(seeds.size(), 1u);
  EXPECT_EQ(seeds[0].frame, 8u);
  Eigen::MatrixXd expected(2, 3);
  expected << 1, 2, 3, 4, 5, 6;
  EXPECT_EQ(seeds[0].Z, expected) << "row-major on the wire";
  EXPECT_EQ(engine.keyframesReceived(), 1u);
}

TEST_F(ClientEngineLevels, FrameChangesAreCoalescedIntoOnePublication) {
  engine.onFrameChanged(kT0);
  EXPECT_EQ(engine.nextWakeUp(), kT0 + ClientEngine::kSecond) << "before a level: installing publishes anyway";
  startedJob(deliverTransfer(engine, tinyPayload("a"), 1, kT0));
  engine.onLevelDecoded(decodedLevel());
  const Micros t = kT0 + Micros{300'000};
  for (int i = 0; i < 3; ++i) engine.onFrameChanged(t + Micros{i});
  EXPECT_EQ(engine.nextWakeUp(), t) << "due at once, from the first change";
  EXPECT_EQ(engine.framesPublished(), 1u) << "nothing published synchronously";
  ClientActions out = engine.tick(t + Micros{5}, {});
  EXPECT_EQ(actionsOf<client_action::PublishFrame>(out).size(), 1u);
  EXPECT_EQ(engine.framesPublished(), 2u);
  EXPECT_EQ(engine.nextWakeUp(), kT0 + ClientEngine::kSecond);
  EXPECT_TRUE(actionsOf<client_action::PublishFrame>(engine.tick(t + Micros{6}, {})).empty());
  engine.leave();
  engine.onFrameChanged(t + Micros{7});
  out = engine.tick(t + Micros{8}, {});
  EXPECT_EQ(actionsOf<client_action::PublishFrame>(out).size(), 1u)
      << "after leave a pending change is still shown (the last Z stays readable)";
}

}  // namespace
}  // namespace sc::session::test
