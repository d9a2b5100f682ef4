// Loopback integration tests of SessionHost and SessionClient (src/session/session_host.cpp, session_client.cpp,
// host_peer_connection.cpp, level_library.cpp): real TCP and UDP sockets on 127.0.0.1, ports chosen by the OS, a
// generated mesh (icosphere, 162 vertices) with a 20-function harmonic basis. Hand-written peers (RawPeer) speak
// the control protocol byte by byte where a test needs what SessionClient refuses to send.
#include "session/session_client.h"
#include "session/session_host.h"

#include <gtest/gtest.h>

#include <QtCore/QtEndian>
#include <QtNetwork/QSslSocket>
#include <QtTest/QSignalSpy>
#include <QtTest/QTest>

#include "harmonic_host_model.h"
#include "model/mesh_decimation.h"
#include "raw_control_peer.h"
#include "session/control_frame.h"
#include "session/handle_transforms.h"
#include "session/host_datagram_channel.h"
#include "session/level_library.h"
#include "session/model_transfer.h"
#include "session/session_clock.h"
#include "session/tls_server.h"
#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"
#include "spectral/resolution_level.h"
#include "test_meshes.h"

#include <memory>

namespace sc::session {
namespace {

constexpr int kWaitMs = 8000;  // generous upper bound for one condition; conditions usually hold in milliseconds

QByteArray toBytes(const std::vector<std::byte>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size())};
}

/// A hand-made peer speaking TLS and raw control messages (tests/session/raw_control_peer.h).
using RawPeer = testing::RawControlPeer;

class SessionLoopback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_model = testing::harmonicHostModel(sc::testing::icosphere(2), 20);
    ASSERT_EQ(s_model->rowCount(), 20);
  }
  static void TearDownTestSuite() { s_model.reset(); }

  static SessionHostOptions hostOptions() {
    SessionHostOptions options;
    options.address = QHostAddress::LocalHost;
    options.pbkdf2Iterations = 1000;  // fast tests; production keeps the default
    options.hostName = QStringLiteral("Hostess");
    return options;
  }

  static std::unique_ptr<SessionHost> startHost(SessionHostOptions options = hostOptions()) {
    auto host = std::make_unique<SessionHost>(s_model, std::move(options));
    QString error;
    EXPECT_TRUE(host->start(&error)) << error.toStdString();
    return host;
  }

  static std::unique_ptr<SessionClient> connectClient(const SessionHost& host, const QString& name,
                                                      std::uint32_t level = 0,
                                                      std::optional<QString> password = std::nullopt) {
    SessionClientOptions options;
    options.host = QStringLiteral("127.0.0.1");
    options.port = host.tcpPort();
    options.name = name;
    options.level = level;
    options.password = std::move(password);
    auto client = std::make_unique<SessionClient>(std::move(options));
    client->start();
    return client;
  }

  /// Waits until the client has its level (Ready) or ended; true when Ready.
  static bool waitReady(SessionClient& client) {
    (void)QTest::qWaitFor(
        [&] {
          const auto s = client.state();
          return s == SessionClient::State::Ready || s == SessionClient::State::Failed ||
                 s == SessionClient::State::Left;
        },
        kWaitMs);
    return client.state() == SessionClient::State::Ready;
  }

  static std::unique_ptr<SessionClient> join(const SessionHost& host, const QString& name, std::uint32_t level = 0) {
    auto client = connectClient(host, name, level);
    EXPECT_TRUE(waitReady(*client)) << name.toStdString() << ": " << client->errorText().toStdString();
    return client;
  }

  static std::uint32_t n() { return static_cast<std::uint32_t>(s_model->vertexCount()); }

  /// Handle: the cap z > 0.8; anchors: z < −0.5.
  static std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>> capConstraints() {
    std::vector<std::uint32_t> handle, anchors;
    for (Eigen::Index i = 0; i < s_model->V.rows(); ++i) {
      if (s_model->V(i, 2) > 0.8) handle.push_back(static_cast<std::uint32_t>(i));
      if (s_model->V(i, 2) < -0.5) anchors.push_back(static_cast<std::uint32_t>(i));
    }
    return {handle, anchors};
  }

  static HandleTransform lift(double dz) {
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.0, dz);
    return toWire(0, pose);
  }

  static inline std::shared_ptr<const HostModel> s_model;
};

TEST_F(SessionLoopback, LevelLibraryPicksTheClosestTargetAndBuildsOnce) {
  LevelLibrary library(s_model);
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
  // Hashed once, on the worker, with the payload.
  EXPECT_EQ(library.find(n())->sha256, sha256(library.find(n())->payload));
  EXPECT_EQ(library.find(target)->sha256, sha256(library.find(target)->payload));
  library.request(target);  // cached: nothing more
  QTest::qWait(50);
  EXPECT_EQ(ready.size(), 2u);
}

TEST_F(SessionLoopback, JoinAndLeaveUpdatePeerLists) {
  auto host = startHost();
  auto alice = join(*host, QStringLiteral("alice"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return alice->peers().peers.size() == 2; }, kWaitMs));
  EXPECT_EQ(alice->peers().peers[0].peerId, kHostPeer);
  EXPECT_EQ(alice->peers().peers[0].name, QStringLiteral("Hostess"));
  EXPECT_EQ(alice->peerId(), 2u);

  auto bob = join(*host, QStringLiteral("bob"));
  EXPECT_EQ(bob->peerId(), 3u);
  // Bob's entry carries his level once his transfer is complete; everybody ends with the host's list.
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return alice->peers() == host->peerList() && bob->peers() == host->peerList(); }, kWaitMs));
  ASSERT_EQ(bob->peers().peers.size(), 3u);
  EXPECT_EQ(bob->peers().peers[2].name, QStringLiteral("bob"));
  EXPECT_EQ(bob->peers().peers[2].vertexCount, n());

  bob->leave();
  EXPECT_EQ(bob->state(), SessionClient::State::Left);
  ASSERT_TRUE(QTest::qWaitFor([&] { return alice->peers().peers.size() == 2; }, kWaitMs));
  EXPECT_EQ(host->peerList().peers.size(), 2u);

  // A taken name is refused.
  auto twin = connectClient(*host, QStringLiteral("alice"));
  EXPECT_FALSE(waitReady(*twin));
  ASSERT_TRUE(twin->handshake().refusal().has_value());
  EXPECT_EQ(twin->handshake().refusal()->reason, RefuseReason::BadName);

  // Host shutdown: Leave to everybody.
  host->shutdown();
  ASSERT_TRUE(QTest::qWaitFor([&] { return alice->state() == SessionClient::State::Left; }, kWaitMs));
  EXPECT_EQ(alice->errorText(), QStringLiteral("the host ended the session"));
}

TEST_F(SessionLoopback, FullModelTransferIsBitExact) {
  auto host = startHost();
  auto client = join(*host, QStringLiteral("full"));
  const QByteArray expected = toBytes(
      spectral::encodeResolutionLevel(spectral::fullResolutionLevel(s_model->V, s_model->F, s_model->basis.vectors)));
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
  EXPECT_EQ(level->payload, toBytes(spectral::encodeResolutionLevel(spectral::resolutionLevel(
                                s_model->V, s_model->F, s_model->basis.vectors, low.V, low.F))));
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

TEST_F(SessionLoopback, LateJoinGetsTheCurrentDeformationAtOnce) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);  // no refresh frames: the keyframe alone must carry Z
  auto host = startHost(options);
  ASSERT_TRUE(host->requestLock());
  ASSERT_EQ(host->lockHolder(), kHostPeer);
  const auto [handle, anchors] = capConstraints();
  spectral::ConstraintSet set;
  set.handles.push_back({std::vector<int>(handle.begin(), handle.end())});
  set.anchors.assign(anchors.begin(), anchors.end());
  ASSERT_TRUE(host->setConstraints(set));
  spectral::HandleTransform pose;
  pose.translation = Eigen::Vector3d(0.0, 0.0, 0.4);
  ASSERT_TRUE(host->drag(std::span(&pose, 1)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->currentFrame() >= 1; }, kWaitMs));  // may be coalesced
  // The still frame after the drag (same Z) goes out before the late join: no datagram frame follows the join.
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().stillFramesSent == 1; }, kWaitMs));
  const Eigen::MatrixXd expected = host->coefficients();
  ASSERT_GT(expected.norm(), 0.0);

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
  const auto top = static_cast<std::size_t>(handle.front());
  ASSERT_TRUE(QTest::qWaitFor([&] { return late->positionsFrame() == keyframe->first; }, kWaitMs));
  EXPECT_GT(late->positions()[3 * top + 2], static_cast<float>(s_model->V(handle.front(), 2)) + 0.2f);
  // The lock holder is announced to the newcomer.
  ASSERT_TRUE(QTest::qWaitFor([&] { return late->lock()->holder() == kHostPeer; }, kWaitMs));
}

TEST_F(SessionLoopback, WrongPasswordIsRefusedWithItsReason) {
  SessionHostOptions options = hostOptions();
  options.password = QStringLiteral("open sesame");
  auto host = startHost(options);

  auto wrong = connectClient(*host, QStringLiteral("mallory"), 0, QStringLiteral("open barley"));
  EXPECT_FALSE(waitReady(*wrong));
  EXPECT_EQ(wrong->state(), SessionClient::State::Failed);
  ASSERT_TRUE(wrong->handshake().refusal().has_value());
  EXPECT_EQ(wrong->handshake().refusal()->reason, RefuseReason::WrongPassword);
  EXPECT_EQ(wrong->errorText(), wrong->handshake().refusal()->text);
  EXPECT_FALSE(wrong->errorText().isEmpty());
  EXPECT_EQ(host->counters().refusalsFor(RefuseReason::WrongPassword), 1u);

  auto none = connectClient(*host, QStringLiteral("nopass"));
  EXPECT_FALSE(waitReady(*none));
  EXPECT_EQ(none->handshake().failure(), ClientFailure::PasswordRequired);

  auto right = connectClient(*host, QStringLiteral("alice"), 0, QStringLiteral("open sesame"));
  EXPECT_TRUE(waitReady(*right)) << right->errorText().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 2; }, kWaitMs));
}

TEST_F(SessionLoopback, VersionMismatchIsRefusedBeforeAnythingElse) {
  auto host = startHost();
  RawPeer peer(host->tcpPort());
  ASSERT_TRUE(peer.connected());
  // Hello of a hypothetical version 99, built by hand: u32 length · u8 type · magic · version · nameLen · name.
  QByteArray hello;
  const QByteArray body = QByteArray::fromHex("5343") + char(99) + char(3) + QByteArray("bob") + QByteArray("future");
  hello.resize(4);
  qToBigEndian<quint32>(static_cast<quint32>(1 + body.size()), hello.data());
  hello += char(0x40);
  hello += body;
  peer.sendRaw(hello);
  const std::optional<Refused> refused = peer.take<Refused>();
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RefuseReason::VersionMismatch);
  EXPECT_EQ(refused->hostVersion, kProtocolVersion);
  EXPECT_TRUE(refused->text.contains(QStringLiteral("99"))) << refused->text.toStdString();
  EXPECT_TRUE(peer.closedByHost());
  EXPECT_FALSE(peer.take<Welcome>(100).has_value());
  EXPECT_EQ(host->counters().refusalsFor(RefuseReason::VersionMismatch), 1u);
}

TEST_F(SessionLoopback, TwoClientsContendForTheLockFifoWithoutDoubleGrant) {
  auto host = startHost();
  auto a = join(*host, QStringLiteral("a"));
  auto b = join(*host, QStringLiteral("b"));
  int doubleGrants = 0;
  const auto check = [&] {
    if (a->lock()->canDrag() && b->lock()->canDrag()) ++doubleGrants;
  };
  QObject::connect(a.get(), &SessionClient::lockChanged, a.get(), check);
  QObject::connect(b.get(), &SessionClient::lockChanged, b.get(), check);

  ASSERT_TRUE(a->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return a->lock()->canDrag(); }, kWaitMs));
  ASSERT_TRUE(b->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->state() == LockState::Queued; }, kWaitMs));
  EXPECT_EQ(b->lock()->queuePosition(), 1u);
  EXPECT_EQ(host->lockHolder(), a->peerId());
  ASSERT_EQ(host->lockQueue().size(), 1u);
  EXPECT_EQ(host->lockQueue().front(), b->peerId());
  const LockEpoch first = a->lock()->heldEpoch();

  // The holder keeps it past the 3 s lease through renewals.
  QTest::qWait(3500);
  EXPECT_TRUE(a->lock()->canDrag());
  EXPECT_EQ(host->lockHolder(), a->peerId());

  ASSERT_TRUE(a->releaseLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->canDrag(); }, kWaitMs));
  EXPECT_GT(b->lock()->heldEpoch(), first);
  ASSERT_TRUE(QTest::qWaitFor([&] { return a->lock()->state() == LockState::Idle; }, kWaitMs));
  EXPECT_EQ(a->lock()->holder(), b->peerId());
  EXPECT_EQ(doubleGrants, 0);
}

TEST_F(SessionLoopback, LockIsFreedWhenTheHoldersConnectionVanishes) {
  auto host = startHost();
  auto a = join(*host, QStringLiteral("a"));
  auto b = join(*host, QStringLiteral("b"));
  ASSERT_TRUE(a->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return a->lock()->canDrag(); }, kWaitMs));
  ASSERT_TRUE(b->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->state() == LockState::Queued; }, kWaitMs));

  a.reset();  // no Leave: the socket just goes away
  QElapsedTimer clock;
  clock.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->lock()->canDrag(); }, 4000));
  EXPECT_LT(clock.elapsed(), 4000);
  EXPECT_EQ(host->lockHolder(), b->peerId());
  ASSERT_TRUE(QTest::qWaitFor([&] { return b->peers().peers.size() == 2; }, kWaitMs));

  // Same without a queue: a raw peer holding the lock disappears; the lock is free.
  {
    RawPeer raw(host->tcpPort());
    const std::optional<Welcome> welcome = raw.join(QStringLiteral("raw"));
    ASSERT_TRUE(welcome.has_value());
    ASSERT_TRUE(b->releaseLock());
    ASSERT_TRUE(QTest::qWaitFor([&] { return host->lockHolder() == kNoPeer; }, kWaitMs));
    ASSERT_NE(raw.acquireLock(welcome->peerId), kNoEpoch);
    EXPECT_EQ(host->lockHolder(), welcome->peerId);
  }
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->lockHolder() == kNoPeer; }, 4000));
}

TEST_F(SessionLoopback, DragsAndConstraintsWithoutTheLockOrWithAStaleEpochAreRejected) {
  auto host = startHost();
  RawPeer raw(host->tcpPort());
  const std::optional<Welcome> welcome = raw.join(QStringLiteral("raw"));
  ASSERT_TRUE(welcome.has_value());
  const auto [handle, anchors] = capConstraints();

  // No lock.
  raw.send(Drag{7, {lift(0.1)}});
  raw.send(Constraints{7, {handle}, anchors});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().constraintsRejected == 1; }, kWaitMs));
  EXPECT_EQ(host->counters().dragsNotHolder, 1u);
  EXPECT_EQ(host->counters().dragsAccepted, 0u);

  // Lock held under a second grant; the first grant's epoch is stale.
  const LockEpoch first = raw.acquireLock(welcome->peerId);
  ASSERT_NE(first, kNoEpoch);
  raw.send(LockMessage{LockRequestKind::Release, first});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->lockHolder() == kNoPeer; }, kWaitMs));
  const LockEpoch second = raw.acquireLock(welcome->peerId);
  ASSERT_GT(second, first);
  raw.send(Drag{first, {lift(0.1)}});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().dragsStale == 1; }, kWaitMs));

  // Vertex ids out of range: rejected; valid ones accepted; then a drag with the right epoch makes a frame.
  raw.send(Constraints{second, {{n() + 5}}, {}});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().constraintsRejected == 2; }, kWaitMs));
  raw.send(Constraints{second, {handle}, anchors});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().constraintsAccepted == 1; }, kWaitMs));
  const std::uint32_t before = host->currentFrame();
  raw.send(Drag{second, {lift(0.1)}});
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().dragsAccepted == 1; }, kWaitMs));
  EXPECT_GT(host->currentFrame(), before);
  EXPECT_GT(host->coefficients().norm(), 0.0);

  // A message a client must never send ends the connection and is counted.
  raw.send(Welcome{*welcome});
  EXPECT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().protocolErrors, 1u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 1; }, kWaitMs));
}

TEST_F(SessionLoopback, GarbageAfterWelcomeClosesTheConnection) {
  auto host = startHost();
  RawPeer raw(host->tcpPort());
  ASSERT_TRUE(raw.join(QStringLiteral("raw")).has_value());
  raw.sendRaw(QByteArray::fromHex("ffffffff00"));  // length beyond the limit
  EXPECT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().protocolErrors, 1u);

  // Before the Welcome the same earns a Refused(ProtocolError).
  RawPeer early(host->tcpPort());
  ASSERT_TRUE(early.connected());
  early.sendRaw(QByteArray::fromHex("0000000140"));  // a Hello without a body
  const std::optional<Refused> refused = early.take<Refused>();
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RefuseReason::ProtocolError);
  EXPECT_TRUE(early.closedByHost());
}

TEST_F(SessionLoopback, SilentPeerIsDropped) {
  SessionHostOptions options = hostOptions();
  options.peerTimeout = std::chrono::milliseconds(1500);
  auto host = startHost(options);
  RawPeer raw(host->tcpPort());  // never sends a heartbeat
  ASSERT_TRUE(raw.join(QStringLiteral("quiet")).has_value());
  EXPECT_TRUE(raw.closedByHost());
  EXPECT_EQ(host->counters().silentPeersDropped, 1u);
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

TEST_F(SessionLoopback, ZChangesWithinOneEventLoopPassAreReconstructedOnce) {
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
  const spectral::ResolutionLevel& level = *client->level();
  const Eigen::MatrixXd Z = Eigen::MatrixXd::Constant(m, 3, 0.03);
  for (const Eigen::Index i : {Eigen::Index{0}, level.restV.rows() / 2, level.restV.rows() - 1}) {
    for (int c = 0; c < 3; ++c) {
      const double expected = level.restV(i, c) + level.K.row(i).transpose().cast<double>().dot(Z.col(c));
      EXPECT_NEAR(client->positions()[static_cast<std::size_t>(3 * i + c)], expected, 1e-5);
    }
  }
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

// --- the still frame after a drag stops (still_frame_schedule.h) and the extrapolating client's view of it

class StillFrameLoopback : public SessionLoopback {
 protected:
  static constexpr int kDragSpacingMs = 50;  ///< drag poses this far apart: one frame each (above `coalesce`)
  static constexpr int kDragSteps = 12;

  /// The host's own user takes the lock, sets the cap constraints and drags the cap up in kDragSteps poses
  /// kDragSpacingMs apart, then stops. Returns the frame number of the last drag's frame (0 on failure).
  static std::uint32_t dragThenStop(SessionHost& host) {
    if (!host.requestLock() || host.lockHolder() != kHostPeer) return 0;
    const auto [handle, anchors] = capConstraints();
    spectral::ConstraintSet set;
    set.handles.push_back({std::vector<int>(handle.begin(), handle.end())});
    set.anchors.assign(anchors.begin(), anchors.end());
    if (!host.setConstraints(set)) return 0;
    QTest::qWait(kDragSpacingMs);
    for (int step = 1; step <= kDragSteps; ++step) {
      spectral::HandleTransform pose;
      pose.translation = Eigen::Vector3d(0.0, 0.0, 0.03 * step);
      if (!host.drag(std::span(&pose, 1))) return 0;
      if (step < kDragSteps) QTest::qWait(kDragSpacingMs);
    }
    return host.currentFrame();
  }

  /// What an extrapolating client displayed, one entry per frameUpdated.
  struct Shown {
    std::uint32_t frame = 0;     ///< currentFrame(): a predicted frame number included
    std::uint32_t received = 0;  ///< receivedFrame()
    Micros at{0};
    Eigen::MatrixXd Z;
  };
  /// Records every frameUpdated of `client`'s channel from now on.
  static std::shared_ptr<std::vector<Shown>> record(SessionClient& client) {
    auto shown = std::make_shared<std::vector<Shown>>();
    ClientDatagramChannel* channel = &client.channel();
    QObject::connect(channel, &ClientDatagramChannel::frameUpdated, channel, [shown, channel](std::uint32_t frame) {
      shown->push_back({frame, channel->receivedFrame(), sessionNow(), channel->coefficients()});
    });
    return shown;
  }
  /// Index of the entry showing the complete received frame `frame` (its last datagram, before anything else was
  /// shown: a predicted frame or the next one); -1 when none.
  static int lastOf(const std::vector<Shown>& shown, std::uint32_t frame) {
    int found = -1;
    for (int i = 0; i < static_cast<int>(shown.size()); ++i) {
      const Shown& entry = shown[static_cast<std::size_t>(i)];
      const bool real = entry.frame == frame && entry.received == frame;
      if (real) found = i;
      if (!real && found >= 0) break;
    }
    return found;
  }
  /// Arrival of frame `frame`'s first datagram (when FramePredictor's overdue schedule starts); 0 when none.
  static Micros arrivalOf(const std::vector<Shown>& shown, std::uint32_t frame) {
    for (const Shown& entry : shown) {
      if (entry.received == frame) return entry.at;
    }
    return Micros{0};
  }
};

TEST_F(StillFrameLoopback, OneStillFrameFollowsTheLastDragThenOnlyTheIdleRefresh) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(400);
  auto host = startHost(options);
  std::vector<std::pair<std::uint32_t, Micros>> sent;
  QObject::connect(host.get(), &SessionHost::frameSent, host.get(),
                   [&sent](std::uint32_t frame) { sent.emplace_back(frame, sessionNow()); });
  const std::uint32_t last = dragThenStop(*host);
  ASSERT_GT(last, 0u);
  const Eigen::MatrixXd dragged = host->coefficients();
  const Micros lastAt = sent.back().second;
  ASSERT_EQ(sent.back().first, last);
  EXPECT_EQ(host->counters().stillFramesSent, 0u);
  // Past the still frame and one idle refresh, short of a second refresh.
  QTest::qWait(options.idleRefresh.count() + 250);

  ASSERT_GE(sent.size(), 2u + kDragSteps);
  std::vector<std::pair<std::uint32_t, Micros>> after;
  for (const auto& entry : sent) {
    if (entry.second > lastAt) after.push_back(entry);
  }
  // Exactly one still frame, the next frame number, within about two drag intervals (1.25 × the measured one).
  EXPECT_EQ(host->counters().stillFramesSent, 1u);
  ASSERT_GE(after.size(), 2u);
  EXPECT_EQ(after[0].first, last + 1);
  const Micros stillGap = after[0].second - lastAt;
  EXPECT_GE(stillGap, StillFrameSchedule::kMinDelay - Micros{1000});
  EXPECT_LE(stillGap, Micros{2 * kDragSpacingMs * 1000});
  EXPECT_EQ(host->coefficients(), dragged);  // the same Z under the new number
  // Then only the idle refresh: a second frame no sooner than idleRefresh after the still frame (the housekeeping
  // tick checks every 100 ms), and nothing else.
  EXPECT_EQ(after.size(), 2u);
  EXPECT_EQ(after[1].first, last + 2);
  const Micros refreshGap = after[1].second - after[0].second;
  EXPECT_GE(refreshGap, std::chrono::duration_cast<Micros>(options.idleRefresh) - Micros{1000});
  EXPECT_LE(refreshGap, std::chrono::duration_cast<Micros>(options.idleRefresh) + Micros{150'000});
}

TEST_F(StillFrameLoopback, ExtrapolatingClientShowsTheLastRealFrameAfterTheDragStops) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);  // only the drag's frames and the still frame
  auto host = startHost(options);
  auto viewer = join(*host, QStringLiteral("viewer"));
  ASSERT_NE(viewer->channel().predictor(), nullptr) << "Extrapolate is the default";
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kWaitMs));
  const std::shared_ptr<std::vector<Shown>> shown = record(*viewer);
  const std::uint32_t last = dragThenStop(*host);
  ASSERT_GT(last, 0u);
  QTest::qWait(250);  // the still frame, and the ~200 ms a withdrawn prediction would have taken

  const int real = lastOf(*shown, last);
  ASSERT_GE(real, 0);
  const Eigen::MatrixXd lastReal = (*shown)[static_cast<std::size_t>(real)].Z;
  EXPECT_LT((lastReal - host->coefficients()).cwiseAbs().maxCoeff(), 1e-3 * host->coefficients().cwiseAbs().maxCoeff());
  // After the last real frame: only the still frame, showing exactly its Z; no predicted frame, no withdrawal.
  ASSERT_GT(shown->size(), static_cast<std::size_t>(real) + 1);
  for (std::size_t i = static_cast<std::size_t>(real) + 1; i < shown->size(); ++i) {
    EXPECT_EQ((*shown)[i].frame, last + 1) << i;
    EXPECT_EQ((*shown)[i].received, last + 1) << i;
    EXPECT_EQ((*shown)[i].Z, lastReal) << i;
  }
  EXPECT_EQ(viewer->channel().currentFrame(), last + 1);
  EXPECT_EQ(viewer->channel().coefficients(), lastReal);
  EXPECT_EQ(viewer->channel().predictor()->withdrawals(), 0u);
  EXPECT_FALSE(viewer->channel().predictor()->nextDue().has_value());
}

TEST_F(StillFrameLoopback, WithoutTheStillFrameThePredictionIsWithdrawnInTime) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);
  options.stillFrame = false;  // as if the still frame were lost on the way
  auto host = startHost(options);
  auto viewer = join(*host, QStringLiteral("viewer"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kWaitMs));
  const std::shared_ptr<std::vector<Shown>> shown = record(*viewer);
  std::optional<Micros> withdrawnAt;
  QObject::connect(&viewer->channel(), &ClientDatagramChannel::predictionWithdrawn, viewer.get(),
                   [&withdrawnAt](std::uint32_t) { withdrawnAt = sessionNow(); });
  const std::uint32_t last = dragThenStop(*host);
  ASSERT_GT(last, 0u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return withdrawnAt.has_value(); }, 2000));
  QTest::qWait(50);

  const int real = lastOf(*shown, last);
  ASSERT_GE(real, 0);
  const Shown& lastReal = (*shown)[static_cast<std::size_t>(real)];
  // Predicted frames last+1..last+4 were shown (the overshoot the still frame avoids), then frame `last` again,
  // (overdueFactor + maxFrames) = 5.5 intervals after it arrived (the documented bound), a timer's slack allowed.
  const Micros interval = viewer->channel().predictor()->interval();
  ASSERT_GT(interval.count(), 0);
  EXPECT_EQ(shown->back().frame, last);
  EXPECT_EQ(shown->back().Z, lastReal.Z);
  EXPECT_EQ(viewer->channel().coefficients(), lastReal.Z);
  EXPECT_GE(viewer->channel().predictor()->framesPredicted(), 4u);
  const Micros withdrawal = *withdrawnAt - arrivalOf(*shown, last);
  const PredictorSettings settings;
  const auto bound = Micros{
      static_cast<Micros::rep>((settings.overdueFactor + settings.maxFrames) * static_cast<double>(interval.count()))};
  EXPECT_GE(withdrawal, bound - Micros{2000});
  EXPECT_LE(withdrawal, bound + Micros{30'000});
}

}  // namespace
}  // namespace sc::session
