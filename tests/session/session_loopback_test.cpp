// Loopback integration tests of SessionHost and SessionClient (src/session/session_host.cpp, session_client.cpp,
// host_peer_connection.cpp, level_library.cpp): real TCP and UDP sockets on 127.0.0.1, ports chosen by the OS, a
// generated mesh (icosphere, 162 vertices) with a 20-function harmonic basis. Hand-written peers (RawPeer) speak
// the control protocol byte by byte where a test needs what SessionClient refuses to send.
#include "session/session_client.h"
#include "session/session_host.h"

#include <gtest/gtest.h>

#include <QtCore/QtEndian>
#include <QtNetwork/QTcpSocket>
#include <QtTest/QTest>

#include "model/mesh_decimation.h"
#include "session/control_frame.h"
#include "session/handle_transforms.h"
#include "session/host_datagram_channel.h"
#include "session/level_library.h"
#include "session/model_transfer.h"
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

/// A control connection driven by hand: every decoded message from the host is kept in order.
class RawPeer {
 public:
  explicit RawPeer(quint16 port) {
    QObject::connect(&m_socket, &QTcpSocket::readyRead, &m_socket, [this] {
      m_reader.append(m_socket.readAll());
      while (auto result = m_reader.next()) {
        if (result->error == ControlError::None) m_received.push_back(result->message);
      }
    });
    m_socket.connectToHost(QHostAddress::LocalHost, port);
  }
  bool connected() {
    return QTest::qWaitFor([this] { return m_socket.state() == QAbstractSocket::ConnectedState; });
  }
  void send(const ControlMessage& message) { m_socket.write(encodeControlMessage(message)); }
  void sendRaw(const QByteArray& bytes) { m_socket.write(bytes); }
  bool closedByHost() {
    return QTest::qWaitFor([this] { return m_socket.state() == QAbstractSocket::UnconnectedState; }, kWaitMs);
  }
  /// Waits for the first received message of type T not yet taken, and takes it.
  template <typename T>
  std::optional<T> take(int timeoutMs = kWaitMs) {
    std::optional<T> found;
    (void)QTest::qWaitFor(
        [&] {
          for (auto it = m_received.begin(); it != m_received.end(); ++it) {
            if (std::holds_alternative<T>(*it)) {
              found = std::get<T>(*it);
              m_received.erase(it);
              return true;
            }
          }
          return false;
        },
        timeoutMs);
    return found;
  }
  /// Hello (open session) → the Welcome.
  std::optional<Welcome> join(const QString& name) {
    if (!connected()) return std::nullopt;
    send(Hello{kProtocolVersion, name});
    return take<Welcome>();
  }
  /// Requests the lock and waits for its grant to this peer.
  LockEpoch acquireLock(PeerId self) {
    send(LockMessage{LockRequestKind::Request, kNoEpoch});
    for (int i = 0; i < 10; ++i) {
      const std::optional<LockNotice> notice = take<LockNotice>();
      if (!notice) return kNoEpoch;
      if (notice->kind == LockNoticeKind::Granted && notice->peer == self) return notice->epoch;
    }
    return kNoEpoch;
  }

 private:
  QTcpSocket m_socket;
  ControlFrameReader m_reader;
  std::vector<ControlMessage> m_received;
};

class SessionLoopback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const testing::GeneratedMesh mesh = testing::icosphere(2);
    auto model = std::make_shared<HostModel>();
    model->V = mesh.V;
    model->F = mesh.F;
    model->operators = spectral::laplaceOperators(mesh.V, mesh.F);
    spectral::BasisOptions options;
    options.m = 20;
    spectral::BasisResult basis = spectral::manifoldHarmonicBasis(model->operators, options);
    ASSERT_TRUE(basis.ok()) << basis.message;
    model->basis = std::move(basis.basis);
    s_model = std::move(model);
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

}  // namespace
}  // namespace sc::session
