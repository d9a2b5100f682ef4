// Loopback tests of the model and level transfer (src/session/net/level_library.cpp, model_transfer.cpp and the
// transfer paths of session_host.cpp / session_client.cpp): the host's level library, a bit-exact full model and
// level, the level list's exact counts, switching levels on one connection, and a client destroyed while its level
// decodes. Real sockets on 127.0.0.1. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include "model/mesh_decimation.h"
#include "session/net/level_library.h"
#include "session/wire/level_codec.h"
#include "session/wire/model_transfer.h"
#include "spectral/resolution_level.h"

#include <QtTest/QSignalSpy>
#include <QtTest/QTest>

namespace sc::session {
namespace {

TEST_F(SessionLoopback, LevelLibraryPicksTheClosestTargetAndBuildsOnce) {
  LevelLibrary library(s_model, LevelBuilder{model::levelTargetList, model::decimatedLevel});
  const std::vector<int> targets = model::levelTargets(static_cast<int>(n()));  // 81, 32, 8
  EXPECT_EQ(library.pick(0), n());
  EXPECT_EQ(library.pick(n()), n());
  EXPECT_EQ(library.pick(n() + 100), n());
  EXPECT_EQ(library.pick(150), static_cast<std::uint32_t>(targets[0]));
  EXPECT_EQ(library.pick(40), static_cast<std::uint32_t>(targets[1]));
  EXPECT_EQ(library.pick(1), static_cast<std::uint32_t>(targets[2]));
  std::vector<std::uint32_t> ready;
  QObject::connect(&library, &LevelLibrary::levelReady, &library, [&](std::uint32_t t) { ready.push_back(t); });
  const std::uint32_t target = library.pick(40);
  library.request(target);
  library.request(target);
  library.request(n());
  EXPECT_EQ(library.find(target), nullptr);  // never built on the calling thread
  ASSERT_TRUE(QTest::qWaitFor([&] { return ready.size() == 2; }, kWaitMs));
  QTest::qWait(50);
  EXPECT_EQ(ready, (std::vector<std::uint32_t>{target, n()}));
  ASSERT_NE(library.find(target), nullptr);
  EXPECT_EQ(library.find(n())->kind, TransferKind::FullModel);
  EXPECT_EQ(library.find(n())->vertexCount, n());
  // Hashed once, on the worker, with the payload: the SHA-256 of the decoded (canonical) payload.
  for (const std::uint32_t built : {n(), target}) {
    const LevelLibrary::Level* level = library.find(built);
    const LevelDecompression decoded = decompressLevelPayload(level->payload, 1U << 30);
    ASSERT_TRUE(decoded.ok()) << decoded.error.toStdString();
    EXPECT_LT(level->payload.size(), decoded.payload.size()) << "sent compressed";
    EXPECT_EQ(level->sha256, sha256(decoded.payload));
  }
  library.request(target);  // cached: nothing more
  QTest::qWait(50);
  EXPECT_EQ(ready.size(), 2u);
}

// Issue 19 item 3: the prefetch starts at the first Welcome, before the client says which level it wants; the
// smallest level comes first, so that a low-resolution joiner of a large mesh does not wait for the full model.
TEST_F(SessionLoopback, PrefetchBuildsTheSmallestLevelFirstAndTheFullModelLast) {
  LevelLibrary library(s_model, LevelBuilder{model::levelTargetList, model::decimatedLevel});
  const std::vector<int> targets = model::levelTargets(static_cast<int>(n()));  // 81, 32, 8
  std::vector<std::uint32_t> ready;
  QObject::connect(&library, &LevelLibrary::levelReady, &library, [&](std::uint32_t t) { ready.push_back(t); });
  library.prefetchAll();
  ASSERT_TRUE(QTest::qWaitFor([&] { return ready.size() == 4; }, kWaitMs));
  EXPECT_EQ(ready,
            (std::vector<std::uint32_t>{static_cast<std::uint32_t>(targets[2]), static_cast<std::uint32_t>(targets[1]),
                                        static_cast<std::uint32_t>(targets[0]), n()}));
}

TEST_F(SessionLoopback, FullModelTransferIsBitExact) {
  auto host = startHost();
  auto client = join(*host, QStringLiteral("full"));
  const QByteArray expected = compressLevelPayload(toBytes(
      spectral::encodeResolutionLevel(spectral::fullResolutionLevel(s_model->V, s_model->F, s_model->basis.vectors))));
  EXPECT_EQ(client->levelPayload(), expected);
  EXPECT_EQ(client->levelVertexCount(), n());
  ASSERT_NE(client->level(), nullptr);
  // At rest (Z = 0), the reconstruction is the rest mesh in float32.
  ASSERT_EQ(client->positions().size(), 3 * static_cast<std::size_t>(n()));
  EXPECT_NEAR(client->positions()[5], static_cast<float>(s_model->V(1, 2)), 1e-6f);
  EXPECT_EQ(host->counters().transfersCompleted, 1u);
  EXPECT_TRUE(QTest::qWaitFor([&] { return client->keyframesReceived() >= 1; }, kWaitMs));
}

TEST_F(SessionLoopback, LevelListGivesTheExactCountsOfTheLevelsDownloaded) {
  auto host = startHost();
  auto client = connectClient(*host, QStringLiteral("lister"), 0);
  QSignalSpy lists(client.get(), &SessionClient::levelsChanged);
  ASSERT_TRUE(waitReady(*client)) << client->errorText().toStdString();
  // The host builds the rest of the ladder in the background and re-sends the list as each level is ready.
  ASSERT_TRUE(QTest::qWaitFor([&] { return client->levels().complete(); }, kWaitMs));
  EXPECT_GE(lists.count(), 2);  // after the Welcome, then per level built
  const LevelList list = client->levels();
  ASSERT_EQ(list.total, host->levels().ladder().size() + 1);
  EXPECT_EQ(list.levels.front().levelId, 0);
  EXPECT_EQ(list.levels.front().vertexCount, n());
  EXPECT_EQ(list.levels.front().faceCount, static_cast<std::uint32_t>(s_model->F.rows()));
  // Each listed level, asked for by its exact vertex count, is exactly that level (counts and payload size).
  for (auto it = list.levels.rbegin(); it != list.levels.rend(); ++it) {
    const LevelInfo level = *it;
    ASSERT_TRUE(client->requestResolution(level.vertexCount));
    ASSERT_TRUE(QTest::qWaitFor([&] { return client->levelVertexCount() == level.vertexCount; }, kWaitMs))
        << "level " << int(level.levelId) << " of " << level.vertexCount << " vertices";
    ASSERT_NE(client->level(), nullptr);
    EXPECT_EQ(static_cast<std::uint32_t>(client->level()->restV.rows()), level.vertexCount);
    EXPECT_EQ(static_cast<std::uint32_t>(client->level()->F.rows()), level.faceCount);
    EXPECT_EQ(static_cast<std::uint32_t>(client->levelPayload().size()), level.payloadBytes);
  }
  EXPECT_EQ(client->levels(), list);  // nothing changed meanwhile
}

TEST_F(SessionLoopback, LevelTransferIsBitExactAndSwitchesWithoutReconnect) {
  auto host = startHost();
  std::vector<std::uint32_t> progress;
  auto client = connectClient(*host, QStringLiteral("low"), 30);
  QObject::connect(client.get(), &SessionClient::modelProgress, client.get(),
                   [&](quint64 received, quint64) { progress.push_back(static_cast<std::uint32_t>(received)); });
  ASSERT_TRUE(waitReady(*client)) << client->errorText().toStdString();
  const std::uint32_t target = host->levels().pick(30);
  EXPECT_EQ(target, model::levelTargets(static_cast<int>(n()))[1]);  // 20% of 162 = 32 is the closest to 30
  const LevelLibrary::Level* level = host->levels().find(target);
  ASSERT_NE(level, nullptr);
  EXPECT_EQ(level->kind, TransferKind::Level);
  EXPECT_EQ(client->levelPayload(), level->payload);
  EXPECT_EQ(client->levelVertexCount(), level->vertexCount);
  // ... and equal to an independent build of the same level.
  const model::DecimatedMesh low = model::decimateMesh(s_model->V, s_model->F, static_cast<int>(target));
  EXPECT_EQ(level->payload, compressLevelPayload(toBytes(spectral::encodeResolutionLevel(spectral::resolutionLevel(
                                s_model->V, s_model->F, s_model->basis.vectors, low.V, low.F)))));
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), static_cast<std::uint32_t>(level->payload.size()));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.back().vertexCount == level->vertexCount; }));

  // Switch to the full model on the same connection; the old level stays displayed until the new one is in.
  ASSERT_TRUE(client->requestResolution(0));
  EXPECT_EQ(client->levelVertexCount(), level->vertexCount);
  ASSERT_TRUE(QTest::qWaitFor([&] { return client->levelVertexCount() == n(); }, kWaitMs));
  EXPECT_EQ(client->positions().size(), 3 * static_cast<std::size_t>(n()));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.back().vertexCount == n(); }, kWaitMs));
  EXPECT_EQ(host->counters().transfersCompleted, 2u);
}

TEST_F(SessionLoopback, ClientDestroyedWhileItsLevelDecodesDoesNotCrash) {
  auto host = startHost();
  for (int round = 0; round < 4; ++round) {
    auto client = connectClient(*host, QStringLiteral("brief%1").arg(round), round % 2 == 0 ? 0 : 30);
    bool lastChunk = false;
    QObject::connect(client.get(), &SessionClient::modelProgress, client.get(), [&](quint64 received, quint64 total) {
      if (total > 0 && received == total) lastChunk = true;  // the decode starts right after this signal
    });
    ASSERT_TRUE(QTest::qWaitFor([&] { return lastChunk; }, kWaitMs)) << client->errorText().toStdString();
    client.reset();  // whether the decode is still running or its result is queued: nothing may reach it
    ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 1; }, kWaitMs));
  }
  // The host is unaffected: a new client still gets its level.
  auto after = join(*host, QStringLiteral("after"));
  EXPECT_EQ(after->levelVertexCount(), n());
  EXPECT_FALSE(after->levelDecoding());
}

}  // namespace
}  // namespace sc::session
