// Fault tests of SessionHost and SessionClient over real sockets on 127.0.0.1 (hardening issue, item 4): the host
// vanishing under its clients, a client vanishing mid-transfer, a frozen lock holder, malformed and oversized
// control frames, and 1000 join/leave cycles with the host's peer table and the process's memory checked after.
// Raw peers go through RawControlPeer (raw_control_peer.h), the one place that picks the control transport.
#include "session/net/session_client.h"
#include "session/net/session_host.h"

#include <gtest/gtest.h>

#include <QtCore/QElapsedTimer>
#include <QtCore/QEventLoop>
#include <QtCore/QFile>
#include <QtCore/QTimer>
#include <QtCore/QtEndian>
#include <QtTest/QTest>

#include "address_sanitizer.h"
#include "harmonic_host_model.h"
#include "raw_control_peer.h"
#include "session/net/host_datagram_channel.h"
#include "session/wire/handle_transforms.h"
#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"
#include "test_meshes.h"

#include <cstdio>
#include <functional>
#include <memory>

namespace sc::session {
namespace {

using testing::kRawWaitMs;
using testing::RawControlPeer;

using testing::harmonicHostModel;
using testing::incompressibleHostModel;

/// Runs the event loop until `done()` holds or `timeoutMs` passed; returns done(). Unlike QTest::qWaitFor (which
/// sleeps 10 ms between passes), it blocks only until the next event, so a join of many round trips takes
/// milliseconds: the 1000-cycle test depends on it.
bool waitFast(const std::function<bool()>& done, int timeoutMs = kRawWaitMs) {
  QElapsedTimer clock;
  clock.start();
  QTimer tick;  // bounds each blocking pass
  tick.start(5);
  QEventLoop loop;
  while (!done()) {
    if (clock.elapsed() > timeoutMs) return false;
    loop.processEvents(QEventLoop::WaitForMoreEvents);
    QCoreApplication::sendPostedEvents(nullptr, QEvent::DeferredDelete);
  }
  return true;
}

/// Resident set size of this process now (VmRSS of /proc/self/status), in KiB; 0 if unreadable.
qint64 residentKiB() {
  QFile status(QStringLiteral("/proc/self/status"));
  if (!status.open(QIODevice::ReadOnly)) return 0;
  for (const QByteArray& line : status.readAll().split('\n')) {
    if (line.startsWith("VmRSS:")) return line.mid(6).trimmed().split(' ').front().toLongLong();
  }
  return 0;
}

class SessionFaults : public ::testing::Test {
 protected:
  /// icosphere(2): 162 vertices, m = 20, a full-model payload of a few KiB.
  static void SetUpTestSuite() { s_small = harmonicHostModel(sc::testing::icosphere(2), 20); }
  static void TearDownTestSuite() { s_small.reset(); }

  static SessionHostOptions hostOptions() {
    SessionHostOptions options;
    options.address = QHostAddress::LocalHost;
    options.hostName = QStringLiteral("host");
    return options;
  }
  static std::unique_ptr<SessionHost> startHost(std::shared_ptr<const HostModel> model = s_small,
                                                SessionHostOptions options = hostOptions()) {
    auto host = std::make_unique<SessionHost>(std::move(model), std::move(options));
    QString error;
    EXPECT_TRUE(host->start(&error)) << error.toStdString();
    return host;
  }
  static std::unique_ptr<SessionClient> connectClient(quint16 port, const QString& name) {
    SessionClientOptions options;
    options.port = port;
    options.name = name;
    auto client = std::make_unique<SessionClient>(std::move(options));
    client->start();
    return client;
  }
  static bool waitReady(SessionClient& client) {
    (void)QTest::qWaitFor([&] { return client.state() >= SessionClient::State::Ready; }, kRawWaitMs);
    return client.state() == SessionClient::State::Ready;
  }
  static std::unique_ptr<SessionClient> join(quint16 port, const QString& name) {
    auto client = connectClient(port, name);
    EXPECT_TRUE(waitReady(*client)) << name.toStdString() << ": " << client->errorText().toStdString();
    return client;
  }

  /// The host's own user takes the lock, constrains the top cap (z > 0.8; anchors z < −0.5) of `model` and
  /// lifts it by `dz`; returns once the frame is out.
  static void hostDrags(SessionHost& host, const HostModel& model, double dz) {
    if (host.lockHolder() != kHostPeer) {
      ASSERT_TRUE(host.requestLock());
      ASSERT_EQ(host.lockHolder(), kHostPeer);
      spectral::ConstraintSet set;
      set.handles.emplace_back();
      for (Eigen::Index i = 0; i < model.V.rows(); ++i) {
        if (model.V(i, 2) > 0.8) set.handles.back().vertices.push_back(static_cast<int>(i));
        if (model.V(i, 2) < -0.5) set.anchors.push_back(static_cast<int>(i));
      }
      ASSERT_TRUE(host.setConstraints(set));
    }
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.0, dz);
    const std::uint32_t before = host.currentFrame();
    ASSERT_TRUE(host.drag(std::span(&pose, 1)));
    ASSERT_TRUE(QTest::qWaitFor([&] { return host.currentFrame() > before; }, kRawWaitMs));
  }

  /// True once `client` displays the host's current frame (its datagrams arrived and were reconstructed).
  static bool follows(const SessionHost& host, const SessionClient& client) {
    return QTest::qWaitFor([&] { return client.positionsFrame() == host.currentFrame(); }, kRawWaitMs);
  }

  static inline std::shared_ptr<const HostModel> s_small;
};

TEST_F(SessionFaults, HostVanishingLeavesClientsWithTheirShapeSayingHostLostAndTheyCanJoinAgain) {
  auto host = startHost();
  auto viewer = join(host->tcpPort(), QStringLiteral("viewer"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kRawWaitMs));
  hostDrags(*host, *s_small, 0.4);
  ASSERT_TRUE(follows(*host, *viewer));
  const std::vector<float> shape = viewer->positions();
  const Eigen::MatrixXd Z = viewer->channel().coefficients();
  ASSERT_GT(Z.norm(), 0.0);

  // The host goes away without a Leave: its sockets close as the kernel closes a killed process's.
  host.reset();
  ASSERT_TRUE(QTest::qWaitFor([&] { return viewer->state() == SessionClient::State::Failed; }, kRawWaitMs));
  EXPECT_TRUE(viewer->errorText().startsWith(QStringLiteral("host lost"))) << viewer->errorText().toStdString();
  // The last shape stays: level, Z and positions as they were.
  ASSERT_NE(viewer->level(), nullptr);
  EXPECT_EQ(viewer->positions(), shape);
  EXPECT_EQ(viewer->channel().coefficients(), Z);

  // A new host on another port: the same process joins it with a new client (as the desktop app does).
  auto second = startHost();
  auto again = join(second->tcpPort(), QStringLiteral("viewer"));
  EXPECT_EQ(again->levelVertexCount(), static_cast<std::uint32_t>(s_small->vertexCount()));
  hostDrags(*second, *s_small, 0.2);
  EXPECT_TRUE(follows(*second, *again));
  EXPECT_EQ(viewer->positions(), shape);  // the failed client is untouched by the new session
}

TEST_F(SessionFaults, ClientVanishingMidTransferFreesItsPeerAndTheLock) {
  // icosphere(6), m = 64 with a random basis: incompressible (the host then sends the canonical payload, about
  // 7.4 MB: K alone is 40962 · 64 int16; a harmonic basis of this smooth sphere compresses to a fraction), far
  // above what a 4 KiB receive window, the host's kernel send buffer (on loopback its 64 KiB segments let it grow
  // past 1 MiB) and its 256 KiB transfer high-water mark hold, so the transfer is certainly unfinished.
  const std::shared_ptr<const HostModel> medium = incompressibleHostModel(sc::testing::icosphere(6), 64, 17);
  auto host = startHost(medium);
  auto bystander = join(host->tcpPort(), QStringLiteral("bystander"));
  ASSERT_EQ(host->counters().transfersCompleted, 1u);

  RawControlPeer raw(host->tcpPort(), 4096);
  const std::optional<Welcome> welcome = raw.join(QStringLiteral("doomed"));
  ASSERT_TRUE(welcome.has_value());
  ASSERT_NE(raw.acquireLock(welcome->peerId), kNoEpoch);
  ASSERT_TRUE(bystander->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return bystander->lock()->state() == LockState::Queued; }, kRawWaitMs));

  // The client stops reading before it asks for the model (a process that hangs): the host's transfer stalls
  // behind the 4 KiB window and its own high-water mark.
  raw.stopReading();
  raw.send(ResolutionRequest{0});
  QTest::qWait(300);
  EXPECT_EQ(host->counters().transfersCompleted, 1u) << "the transfer finished: the test did not stall it";
  EXPECT_EQ(host->peerList().peers.back().vertexCount, 0u);  // the doomed peer has no level yet
  EXPECT_EQ(host->lockHolder(), welcome->peerId);

  raw.abort();  // killed: the kernel resets the connection
  QElapsedTimer clock;
  clock.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return bystander->lock()->canDrag(); }, kRawWaitMs));
  EXPECT_LT(clock.elapsed(), 1000);  // at the disconnect, not at a lease expiry
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 2; }, kRawWaitMs));
  EXPECT_FALSE(host->channel().pathOpen(welcome->peerId));
  EXPECT_TRUE(host->lockQueue().empty());

  // The host keeps serving: the bystander drags, a newcomer gets the whole model.
  bystander->sendConstraints({{0}}, {static_cast<std::uint32_t>(medium->vertexCount() - 1)});
  spectral::HandleTransform pose;
  pose.translation = Eigen::Vector3d(0.0, 0.0, 0.1);
  const std::uint32_t before = host->currentFrame();
  ASSERT_TRUE(bystander->sendDrag({toWire(0, pose)}));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->currentFrame() > before; }, kRawWaitMs));
  EXPECT_TRUE(follows(*host, *bystander));
  auto newcomer = join(host->tcpPort(), QStringLiteral("newcomer"));
  EXPECT_EQ(newcomer->levelVertexCount(), static_cast<std::uint32_t>(medium->vertexCount()));
  EXPECT_EQ(host->counters().transfersCompleted, 2u);
}

TEST_F(SessionFaults, FrozenLockHolderLosesTheLockWhenItsLeaseExpires) {
  auto host = startHost();
  auto waiter = join(host->tcpPort(), QStringLiteral("waiter"));
  RawControlPeer frozen(host->tcpPort());
  const std::optional<Welcome> welcome = frozen.join(QStringLiteral("frozen"));
  ASSERT_TRUE(welcome.has_value());
  ASSERT_NE(frozen.acquireLock(welcome->peerId), kNoEpoch);
  // From here the holder sends nothing (no renewal, no heartbeat), as a SIGSTOP'ed process; its socket stays open.
  QElapsedTimer clock;
  clock.start();
  ASSERT_TRUE(waiter->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return waiter->lock()->state() == LockState::Queued; }, kRawWaitMs));
  ASSERT_TRUE(QTest::qWaitFor([&] { return waiter->lock()->canDrag(); }, kRawWaitMs));
  const qint64 elapsed = clock.elapsed();
  EXPECT_GE(elapsed, kLockLease.count() - 100);  // revoked by the lease (3 s), not by anything sooner
  EXPECT_LT(elapsed, 4000);
  EXPECT_EQ(host->lockHolder(), waiter->peerId());
  EXPECT_EQ(host->peerList().peers.size(), 3u);  // frozen, not gone: its connection is still there
  bool revoked = false;  // the release for an expired lease went to everybody, the frozen holder included
  while (const std::optional<LockNotice> notice = frozen.take<LockNotice>(500)) {
    revoked = revoked || (notice->kind == LockNoticeKind::Released && notice->peer == welcome->peerId &&
                          notice->reason == LockReleaseReason::LeaseExpired);
  }
  EXPECT_TRUE(revoked);
}

TEST_F(SessionFaults, MalformedAndOversizedControlFramesCloseOnlyThatConnection) {
  auto host = startHost();
  auto viewer = join(host->tcpPort(), QStringLiteral("viewer"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kRawWaitMs));

  const auto header = [](quint32 length) {
    QByteArray bytes(4, '\0');
    qToBigEndian<quint32>(length, bytes.data());
    return bytes;
  };
  // A Drag cut short: its length covers the type and 3 body bytes only.
  const QByteArray drag = encodeControlMessage(Drag{1, {toWire(0, spectral::HandleTransform{})}});
  ASSERT_GT(drag.size(), 8);
  const QByteArray truncatedDrag = header(4) + drag.mid(4, 4);
  // A frame one byte over the limit, body and all (the host must not buffer it before closing).
  const QByteArray oversized = header(kMaxControlMessageSize + 1) + QByteArray(kMaxControlMessageSize + 1, 'x');
  const QByteArray unknownType = header(3) + QByteArray::fromHex("7f0102");
  const QByteArray zeroLength = header(0);

  std::uint64_t errors = host->counters().protocolErrors;
  double dz = 0.1;
  for (const QByteArray& bad : {truncatedDrag, oversized, unknownType, zeroLength}) {
    RawControlPeer raw(host->tcpPort());
    ASSERT_TRUE(raw.join(QStringLiteral("fuzz")).has_value());
    ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 3; }, kRawWaitMs));
    raw.sendRaw(bad);
    EXPECT_TRUE(raw.closedByHost()) << bad.left(8).toHex().toStdString();
    EXPECT_EQ(host->counters().protocolErrors, ++errors);
    ASSERT_TRUE(QTest::qWaitFor([&] { return host->peerList().peers.size() == 2; }, kRawWaitMs));
    // The other client is served as before.
    hostDrags(*host, *s_small, dz += 0.1);
    EXPECT_TRUE(follows(*host, *viewer)) << bad.left(8).toHex().toStdString();
    EXPECT_EQ(viewer->state(), SessionClient::State::Ready);
  }
  // Before the Welcome, an oversized first frame earns a Refused and the close.
  RawControlPeer early(host->tcpPort());
  ASSERT_TRUE(early.connected());
  early.sendRaw(oversized);
  const std::optional<Refused> refused = early.take<Refused>();
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RefuseReason::ProtocolError);
  EXPECT_TRUE(early.closedByHost());
  auto late = join(host->tcpPort(), QStringLiteral("late"));
  EXPECT_EQ(late->state(), SessionClient::State::Ready);
}

TEST_F(SessionFaults, ThousandJoinLeaveCyclesLeaveNoPeersAndFlatMemory) {
  auto host = startHost();
  constexpr int kCycles = 1000;
  qint64 rssAt100 = 0;
  for (int cycle = 1; cycle <= kCycles; ++cycle) {
    auto client = connectClient(host->tcpPort(), QStringLiteral("cycler"));
    ASSERT_TRUE(waitFast([&] { return client->state() >= SessionClient::State::Ready; }));
    ASSERT_EQ(client->state(), SessionClient::State::Ready) << cycle << ": " << client->errorText().toStdString();
    const PeerId id = client->peerId();
    if (cycle % 2 == 0) {
      client->leave();  // half leave politely, half vanish (destroyed without a Leave)
    }
    client.reset();
    ASSERT_TRUE(waitFast([&] { return host->peerList().peers.size() == 1; })) << cycle;
    ASSERT_FALSE(host->channel().pathOpen(id));
    if (cycle == 100) {
      QTest::qWait(20);  // deferred deletions of the cycle's connection objects
      rssAt100 = residentKiB();
    }
  }
  QTest::qWait(20);
  const qint64 rssAt1000 = residentKiB();
  EXPECT_EQ(host->peerList().peers.size(), 1u);
  EXPECT_TRUE(host->lockQueue().empty());
  EXPECT_EQ(host->counters().transfersCompleted, static_cast<std::uint64_t>(kCycles));
  ASSERT_GT(rssAt100, 0);
  // Bound: 1 MiB over 900 cycles, i.e. < 1.2 KiB per cycle. One leaked client object graph (socket, channel,
  // timers, level: tens of KiB) or one leaked peer entry with its encoder per cycle would exceed it many times,
  // while allocator noise (heap fragmentation, Qt's lazily grown pools) stays well inside it.
  // Under ASan the RSS grows without any leak (freed blocks wait in ASan's quarantine, up to 256 MiB, and their
  // shadow memory stays mapped), so only the bound is skipped there: the cycles and the checks above still run,
  // and LeakSanitizer at exit reports any block the cycles left unreachable (memory that stays reachable but grows
  // is caught by this bound in the normal job, which keeps it).
  if (!sc::testing::kAddressSanitizer) {
    EXPECT_LT(rssAt1000 - rssAt100, 1024)
        << "RSS after cycle 100: " << rssAt100 << " KiB, after " << kCycles << ": " << rssAt1000 << " KiB";
  }
  std::printf("[ memory   ] RSS after cycle 100: %lld KiB, after cycle %d: %lld KiB\n",
              static_cast<long long>(rssAt100), kCycles, static_cast<long long>(rssAt1000));
}

}  // namespace
}  // namespace sc::session
