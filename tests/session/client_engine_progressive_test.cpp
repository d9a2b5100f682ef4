// Tests for the ClientEngine's progressive join (issue 17 item 4; src/session/engine/client_engine_levels.cpp):
// the smallest level is asked for first and shown, the wanted one is asked for once the preview's transfer is in,
// the newest choice wins, the swap shows the latest Z on the new level, and nothing is asked twice when the preview
// already is the wanted level. A fake host and a fake decode worker (the test calls onLevelDecoded()).
#include "client_engine_fixture.h"

namespace sc::session::test {
namespace {

constexpr std::uint32_t kPreviewVertices = 2;  ///< the fake host's smallest rung (n' = 2 < n = 3)
constexpr std::uint32_t kPreviewBytes = 150;   ///< within levelPayloadBounds(2, 1, kRows)

/// A level of kPreviewVertices vertices (P maps them onto the first two full vertices), wrapped for display.
DecodedLevel decodedPreview() {
  spectral::ResolutionLevel level;
  level.restV = Eigen::MatrixXd::Identity(2, 3);
  level.F = Eigen::MatrixXi(1, 3);
  level.F << 0, 1, 1;
  level.P.resize(2, kVertices);
  level.P.insert(0, 0) = 1.0;
  level.P.insert(1, 1) = 1.0;
  level.K = spectral::quantizeBasis(Eigen::MatrixXd::Constant(2, kRows, 0.5));
  return DecodedLevel{QByteArray("preview"), spectral::makeDisplayLevel(std::move(level)), {}};
}

class ClientEngineProgressive : public ::testing::Test {
 protected:
  ClientEngineProgressive() {
    ClientEngineConfig progressive = config("progressive", m_wanted);
    progressive.progressive = true;
    engine = std::make_unique<ClientEngine>(progressive);
  }
  /// Joins; returns the vertex counts the ResolutionRequests asked for.
  std::vector<std::uint32_t> join() { return requested(joinSession(*engine, kT0)); }
  static std::vector<std::uint32_t> requested(const ClientActions& out) {
    std::vector<std::uint32_t> counts;
    for (const ResolutionRequest& r : sent<ResolutionRequest>(out)) counts.push_back(r.vertexCount);
    return counts;
  }
  /// The host's ladder: the full model and the preview level (`complete`), or the preview alone listed.
  void listLevels(bool complete) {
    const auto full = static_cast<std::uint32_t>(tinyPayload("f").size());
    LevelList list{2, {}};
    if (complete) list.levels.push_back(LevelInfo{0, kVertices, 1, full});
    list.levels.push_back(LevelInfo{1, kPreviewVertices, 1, kPreviewBytes});
    engine->onMessage(message(list), kT0);
  }
  /// Sends a transfer of `vertices` (payload of the listed size) as transfer `id`; the actions of its last chunk.
  ClientActions transfer(std::uint32_t vertices, std::uint32_t id) {
    const QByteArray payload = vertices == kVertices ? tinyPayload("full") : QByteArray(kPreviewBytes, 'p');
    const TransferKind kind = vertices == kVertices ? TransferKind::FullModel : TransferKind::Level;
    ModelSender sender(id, kind, vertices, payload, 64);
    ClientActions last = engine->onMessage(message(sender.begin()), kT0);
    while (std::optional<ModelChunk> chunk = sender.nextChunk()) last = engine->onMessage(message(*chunk), kT0);
    return last;
  }

  std::uint32_t m_wanted = 0;
  std::unique_ptr<ClientEngine> engine;
};

TEST_F(ClientEngineProgressive, TheSmallestLevelFirstThenTheWantedOneOnceThePreviewIsIn) {
  EXPECT_EQ(join(), std::vector<std::uint32_t>{ClientEngine::kSmallestLevel}) << "the preview first, alone";
  EXPECT_TRUE(engine->levelPending());
  listLevels(false);
  const ClientActions done = transfer(kPreviewVertices, 1);
  EXPECT_EQ(actionsOf<client_action::StartDecode>(done).size(), 1u) << "the preview decodes";
  EXPECT_EQ(requested(done), std::vector<std::uint32_t>{0}) << "the full model is asked for as the preview completes";
  // The preview shows: Ready, a frame published, and the wanted level still pending.
  ClientActions out = engine->onLevelDecoded(decodedPreview());
  EXPECT_EQ(actionsOf<client_action::LevelReady>(out).at(0).vertexCount, kPreviewVertices);
  EXPECT_EQ(engine->state(), ClientState::Ready);
  EXPECT_TRUE(engine->levelPending());
  // The full model streams in the background; then it replaces the preview.
  listLevels(true);
  out = transfer(kVertices, 2);
  EXPECT_TRUE(requested(out).empty()) << "asked for once";
  out = engine->onLevelDecoded(decodedLevel());
  EXPECT_EQ(actionsOf<client_action::LevelReady>(out).at(0).vertexCount, kVertices);
  EXPECT_EQ(engine->levelVertexCount(), kVertices);
  EXPECT_FALSE(engine->levelPending());
}

TEST_F(ClientEngineProgressive, TheTransferInFlightIsTheBackgroundLevelOnceThePreviewShows) {
  join();
  listLevels(true);
  EXPECT_EQ(engine->transferVertexCount(), 0u);
  transfer(kPreviewVertices, 1);
  engine->onLevelDecoded(decodedPreview());
  const QByteArray payload = tinyPayload("full");
  ModelSender sender(2, TransferKind::FullModel, kVertices, payload, 64);
  engine->onMessage(message(sender.begin()), kT0);
  const ClientActions out = engine->onMessage(message(*sender.nextChunk()), kT0);
  EXPECT_EQ(engine->transferVertexCount(), kVertices) << "what a progress bar names";
  EXPECT_EQ(actionsOf<client_action::ModelProgress>(out).at(0).received, 64u);
  EXPECT_EQ(engine->levelVertexCount(), kPreviewVertices) << "the preview stays shown meanwhile";
}

TEST_F(ClientEngineProgressive, TheNewestChoiceWins) {
  join();
  listLevels(false);
  // Chosen twice while the preview is on its way: nothing is sent, the choice is kept.
  ClientActions out = engine->requestResolution(kVertices);
  EXPECT_TRUE(requested(out).empty());
  EXPECT_EQ(actionsOf<client_action::Notify>(out).at(0).notice, ClientNotice::LevelChoiceKept) << "not refused";
  engine->requestResolution(2000);
  EXPECT_EQ(requested(transfer(kPreviewVertices, 1)), std::vector<std::uint32_t>{2000}) << "the newest choice";
  engine->onLevelDecoded(decodedPreview());
  // Chosen again while the wanted level streams: asked for at once (the host replaces the transfer).
  EXPECT_EQ(requested(engine->requestResolution(0)), std::vector<std::uint32_t>{0});
  EXPECT_TRUE(engine->levelPending());
}

TEST_F(ClientEngineProgressive, ThePreviewIsShownEvenWhenTheWantedLevelCompletesWhileItDecodes) {
  join();
  listLevels(true);
  transfer(kPreviewVertices, 1);                               // the preview decodes ...
  const ClientActions whileDecoding = transfer(kVertices, 2);  // ... while the full model completes
  EXPECT_TRUE(actionsOf<client_action::StartDecode>(whileDecoding).empty()) << "one decode at a time";
  ClientActions out = engine->onLevelDecoded(decodedPreview());
  EXPECT_EQ(actionsOf<client_action::LevelReady>(out).at(0).vertexCount, kPreviewVertices) << "shown all the same";
  EXPECT_EQ(actionsOf<client_action::StartDecode>(out).size(), 1u) << "then the wanted level decodes";
  out = engine->onLevelDecoded(decodedLevel());
  EXPECT_EQ(engine->levelVertexCount(), kVertices);
  EXPECT_FALSE(engine->levelPending());
}

TEST_F(ClientEngineProgressive, TheSwapPublishesTheLatestFrameOnTheNewLevel) {
  join();
  listLevels(true);
  transfer(kPreviewVertices, 1);
  engine->onLevelDecoded(decodedPreview());
  const std::uint64_t before = engine->framesPublished();
  // Frames keep coming while the wanted level streams: each batch is published on the preview ...
  engine->onFrameChanged(kT0 + Micros{10});
  EXPECT_EQ(actionsOf<client_action::PublishFrame>(engine->tick(kT0 + Micros{10}, {})).size(), 1u);
  transfer(kVertices, 2);
  engine->onFrameChanged(kT0 + Micros{20});  // pending when the new level arrives
  // ... and installing the full model publishes at once: the adapter shows the latest Z on it (no rest pose).
  const ClientActions out = engine->onLevelDecoded(decodedLevel());
  ASSERT_EQ(actionsOf<client_action::Notify>(out).at(0).notice, ClientNotice::LevelInstalled);
  EXPECT_EQ(actionsOf<client_action::PublishFrame>(out).size(), 1u);
  EXPECT_EQ(engine->framesPublished(), before + 2);
  EXPECT_TRUE(actionsOf<client_action::PublishFrame>(engine->tick(kT0 + Micros{30}, {})).empty())
      << "the pending change was served by the install";
}

TEST_F(ClientEngineProgressive, NothingMoreIsAskedWhenThePreviewIsTheWantedLevel) {
  // A host without a ladder serves its full model for the preview: a full request is then served.
  join();
  engine->onMessage(message(tinyLevelList(static_cast<std::uint32_t>(tinyPayload("full").size()))), kT0);
  EXPECT_TRUE(requested(transfer(kVertices, 1)).empty());
  EXPECT_FALSE(engine->levelPending());

  // kSmallestLevel itself: no progressive step at all.
  ClientEngineConfig small = config("small", 1);
  small.progressive = true;
  ClientEngine direct(small);
  EXPECT_EQ(requested(joinSession(direct)), std::vector<std::uint32_t>{1});
  EXPECT_FALSE(direct.levelPending());

  // A wanted level whose closest listed level is the preview.
  ClientEngineConfig near = config("near", kPreviewVertices);
  near.progressive = true;
  engine = std::make_unique<ClientEngine>(near);
  join();
  listLevels(true);
  EXPECT_TRUE(requested(transfer(kPreviewVertices, 1)).empty()) << "the complete list says it is the same level";
  EXPECT_FALSE(engine->levelPending());
}

TEST_F(ClientEngineProgressive, AFailedPreviewTransferAsksForTheWantedLevelAtOnce) {
  join();
  listLevels(true);
  const QByteArray payload(kPreviewBytes, 'p');
  engine->onMessage(message(ModelBegin{1, TransferKind::Level, kPreviewVertices, kPreviewBytes, sha256(payload)}), kT0);
  const ClientActions out = engine->onMessage(message(ModelChunk{1, 4, kPreviewBytes, payload.mid(4)}), kT0);
  EXPECT_EQ(actionsOf<client_action::LevelFailed>(out).size(), 1u);
  EXPECT_EQ(requested(out), std::vector<std::uint32_t>{0});
  EXPECT_TRUE(engine->levelPending());
}

TEST_F(ClientEngineProgressive, WithoutTheOptionTheWantedLevelIsAskedForDirectly) {
  ClientEngine plain(config("plain", 1200));
  EXPECT_EQ(requested(joinSession(plain)), std::vector<std::uint32_t>{1200});
  EXPECT_FALSE(plain.levelPending());
}

}  // namespace
}  // namespace sc::session::test
