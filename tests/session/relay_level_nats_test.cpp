// Level payloads through a real nats-server's JetStream stream (issue 18 item 1): a viewer fetches every level of a
// small mesh and gets exactly the payload a TLS joiner's transfer carries (the host LevelLibrary's bytes, same
// SHA-256s); a forged or oversized chunk and a level above the viewer's limit are refused with a reason; a viewer
// cannot publish on a level subject; a viewer that comes late (after the levels were published and the shape moved)
// still gets its level and shows X̂' + K·Z of the relayed frame. Fixture: relay_nats_fixture.h with a ladder.
#include "relay_nats_fixture.h"

#include "model/decimating_level_builder.h"
#include "session/net/level_library.h"
#include "session/net/relay_level_fetcher.h"
#include "session/net/relay_level_publisher.h"
#include "session/wire/relay_level_list.h"

#include <QtCore/QCryptographicHash>

#include <optional>

namespace sc::session {
namespace {

class RelayLevels : public RelayNats {
 protected:
  void configureHost(SessionHostOptions& options) override {
    options.levelBuilder = LevelBuilder{model::levelTargetList, model::decimatedLevel};
  }

  void SetUp() override {
    RelayNats::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    RelayLevelPublisherOptions options;
    options.sessionId = m_server.config().sessionId;
    options.chunkBytes = 1024;  // several chunks per level of this small mesh
    m_levels = std::make_unique<RelayLevelPublisher>(*m_host, *m_publisher->connection(), options);
    QString error;
    ASSERT_TRUE(m_levels->start(&error)) << error.toStdString();
    ASSERT_TRUE(waitFor([&] { return m_levels->complete(); }, 20000)) << m_levels->counters().levels;
  }

  void TearDown() override {
    m_fetchers.clear();
    m_levels.reset();
    RelayNats::TearDown();
  }

  /// A started fetcher of `viewer`'s session.
  RelayLevelFetcher* addFetcher(const RelayViewer& viewer, std::uint64_t maxLevelBytes = 256ull << 20) {
    RelayLevelFetcherOptions options;
    options.sessionId = m_server.config().sessionId;
    options.facts = viewer.receiver().facts();
    options.maxLevelBytes = maxLevelBytes;
    options.listWait = std::chrono::milliseconds(500);
    auto fetcher = std::make_unique<RelayLevelFetcher>(*viewer.connection(), options);
    QString error;
    EXPECT_TRUE(fetcher->start(&error)) << error.toStdString();
    m_fetchers.push_back(std::move(fetcher));
    return m_fetchers.back().get();
  }

  /// Fetches `index` and waits for the outcome.
  static const RelayLevelFetch& fetchNow(RelayLevelFetcher& fetcher, std::uint8_t index) {
    bool done = false;
    const QMetaObject::Connection a =
        QObject::connect(&fetcher, &RelayLevelFetcher::levelReady, [&done] { done = true; });
    const QMetaObject::Connection b =
        QObject::connect(&fetcher, &RelayLevelFetcher::levelRefused, [&done] { done = true; });
    fetcher.fetch(index);
    EXPECT_TRUE(waitFor([&] { return done; }, 20000));
    QObject::disconnect(a);
    QObject::disconnect(b);
    return fetcher.last();
  }

  /// The host library's level for list index `index` (what a TLS joiner's transfer carries).
  const LevelLibrary::Level* hostLevel(std::uint8_t index) const {
    LevelLibrary& levels = m_host->levels();
    const std::uint32_t target = index == 0 ? levels.fullTarget() : levels.ladder().at(index - 1u);
    return levels.find(target);
  }

  /// Publishes `bytes` on a level chunk's subject with the HOST credential (what a compromised broker or a leaked
  /// host credential could do; viewers cannot: see AViewerCannotPublishOnALevelSubject).
  void replaceChunk(std::uint8_t index, std::uint32_t chunk, const QByteArray& bytes) {
    QString why;
    NatsConnectOptions options = viewerCredential();
    options.user = m_server.config().hostUser;
    options.password = m_server.config().hostPassword;
    std::unique_ptr<NatsConnection> rogue = NatsConnection::connect(options, &why);
    ASSERT_TRUE(rogue) << why.toStdString();
    std::unique_ptr<NatsStream> stream = rogue->bindStream(relayLevelStream(m_server.config().sessionId), &why);
    ASSERT_TRUE(stream) << why.toStdString();
    ASSERT_TRUE(stream->publish(relayLevelChunkSubject(m_server.config().sessionId, index, chunk), bytes, &why))
        << why.toStdString();
  }

  std::unique_ptr<RelayLevelPublisher> m_levels;
  std::vector<std::unique_ptr<RelayLevelFetcher>> m_fetchers;
};

TEST_F(RelayLevels, AViewerFetchesEveryLevelWithTheTlsJoinersPayload) {
  const RelayLevelList& list = m_levels->list();
  ASSERT_EQ(list.levels.size(), m_host->levels().ladder().size() + 1);
  ASSERT_GE(list.levels.size(), 2u);
  RelayViewer* viewer = addViewer();
  ASSERT_NE(viewer, nullptr);
  RelayLevelFetcher* fetcher = addFetcher(*viewer);
  QString why;
  const std::optional<RelayLevelList> read = fetcher->readList(&why);
  ASSERT_TRUE(read) << why.toStdString();
  EXPECT_EQ(*read, list);
  std::int64_t chunks = 0;
  for (const RelayLevelEntry& entry : list.levels) {
    const LevelLibrary::Level* host = hostLevel(entry.index);
    ASSERT_NE(host, nullptr);
    const RelayLevelFetch& fetch = fetchNow(*fetcher, entry.index);
    ASSERT_TRUE(fetch.level) << fetch.error.toStdString();
    EXPECT_EQ(fetch.index, entry.index);
    // The same bytes as the TLS path's transfer (ModelBegin::totalSize and ::sha256), published once.
    EXPECT_EQ(entry.payloadBytes, static_cast<std::uint32_t>(host->payload.size()));
    EXPECT_EQ(entry.payloadSha256, QCryptographicHash::hash(host->payload, QCryptographicHash::Sha256));
    EXPECT_EQ(entry.canonicalSha256, host->sha256);
    EXPECT_EQ(fetch.chunks, relayChunkCount(entry.payloadBytes, list.chunkBytes));
    EXPECT_EQ(fetch.level->vertexCount(), host->vertexCount);
    EXPECT_EQ(static_cast<std::uint32_t>(fetch.level->level.F.rows()), host->faceCount);
    EXPECT_EQ(fetch.level->basisSize(), s_model->rowCount());
    chunks += fetch.chunks;
  }
  EXPECT_EQ(m_levels->counters().chunks, chunks);  // every chunk published once
  EXPECT_EQ(m_levels->counters().failures, 0);
  // The full level at rest is the model itself (float32 rest positions).
  const RelayLevelFetch& full = fetchNow(*fetcher, 0);
  ASSERT_TRUE(full.level);
  EXPECT_LT((full.level->level.restV - s_model->V).cwiseAbs().maxCoeff(), 1e-6);
}

TEST_F(RelayLevels, AForgedOrOversizedChunkOrALevelAboveTheLimitIsRefused) {
  const RelayLevelEntry entry = m_levels->list().levels.back();  // the smallest level
  const std::uint32_t chunkBytes = m_levels->list().chunkBytes;
  RelayViewer* viewer = addViewer();
  ASSERT_NE(viewer, nullptr);
  RelayLevelFetcher* fetcher = addFetcher(*viewer);
  ASSERT_TRUE(fetchNow(*fetcher, entry.index).level);  // authentic first

  const QByteArray original = hostLevel(entry.index)->payload.first(relayChunkSize(entry.payloadBytes, chunkBytes, 0));
  QByteArray forged = original;
  forged[0] = static_cast<char>(forged[0] ^ 0x5a);
  replaceChunk(entry.index, 0, forged);
  const RelayLevelFetch& refused = fetchNow(*fetcher, entry.index);
  EXPECT_FALSE(refused.level);
  EXPECT_TRUE(refused.error.contains(QStringLiteral("SHA-256"))) << refused.error.toStdString();

  replaceChunk(entry.index, 0, original + QByteArray(100, 'x'));
  const RelayLevelFetch& oversized = fetchNow(*fetcher, entry.index);
  EXPECT_FALSE(oversized.level);
  EXPECT_TRUE(oversized.error.contains(QStringLiteral("oversized"))) << oversized.error.toStdString();

  replaceChunk(entry.index, 0, original.first(original.size() - 1));
  const RelayLevelFetch& shorter = fetchNow(*fetcher, entry.index);
  EXPECT_FALSE(shorter.level);
  EXPECT_TRUE(shorter.error.contains(QStringLiteral("expected"))) << shorter.error.toStdString();

  replaceChunk(entry.index, 0, original);  // restored: accepted again
  EXPECT_TRUE(fetchNow(*fetcher, entry.index).level);

  RelayLevelFetcher* small = addFetcher(*viewer, /*maxLevelBytes=*/entry.payloadBytes - 1);
  const RelayLevelFetch& tooLarge = fetchNow(*small, entry.index);
  EXPECT_FALSE(tooLarge.level);
  EXPECT_TRUE(tooLarge.error.contains(QStringLiteral("limit"))) << tooLarge.error.toStdString();
  EXPECT_EQ(tooLarge.chunks, 0u);  // refused before reading any chunk

  const RelayLevelFetch& unlisted = fetchNow(*fetcher, static_cast<std::uint8_t>(kMaxLevels - 1));
  EXPECT_FALSE(unlisted.level);
  EXPECT_TRUE(unlisted.error.contains(QStringLiteral("not published"))) << unlisted.error.toStdString();
}

TEST_F(RelayLevels, AViewerCannotPublishOnALevelSubject) {
  QString why;
  std::unique_ptr<NatsConnection> rogue = NatsConnection::connect(viewerCredential(), &why);
  ASSERT_TRUE(rogue) << why.toStdString();
  rogue->publish(relayLevelChunkSubject(m_server.config().sessionId, 0, 0), QByteArray(16, 'x'));
  rogue->flush(std::chrono::milliseconds(2000));
  ASSERT_TRUE(waitFor([&] { return rogue->lastError().contains(QStringLiteral("Permissions Violation")); }))
      << rogue->lastError().toStdString();
  RelayViewer* viewer = addViewer();
  ASSERT_NE(viewer, nullptr);
  EXPECT_TRUE(fetchNow(*addFetcher(*viewer), 0).level);  // the stream is unchanged
}

TEST_F(RelayLevels, ALateViewerStillGetsItsLevelAndShowsTheRelayedShape) {
  for (int step = 1; step <= 8; ++step) dragOnce(0.03 * step);
  QTest::qWait(400);  // the trailing keyframe
  RelayViewer* late = addViewer();
  ASSERT_NE(late, nullptr);
  ASSERT_EQ(late->receiver().coefficients(), m_host->coefficients());
  const RelayLevelFetch& fetch = fetchNow(*addFetcher(*late), 0);  // the full level: the cap's own vertices
  ASSERT_TRUE(fetch.level) << fetch.error.toStdString();
  // X̂' + K·Z with the relayed Z is the host's shape mapped to the level: P·(deformed V) within K's quantisation.
  spectral::DisplayFrame frame;
  frame.Z = late->receiver().coefficients().cast<float>();
  const std::vector<float> shown = spectral::reconstructed(*fetch.level, frame);
  const std::vector<float> rest = spectral::reconstructed(*fetch.level, spectral::DisplayFrame{});
  ASSERT_EQ(shown.size(), 3u * fetch.level->vertexCount());
  double moved = 0;
  for (std::size_t i = 0; i < shown.size(); ++i) moved = std::max(moved, std::abs(double(shown[i]) - rest[i]));
  EXPECT_GT(moved, 0.01);  // deformed, not the rest shape
}

}  // namespace
}  // namespace sc::session
