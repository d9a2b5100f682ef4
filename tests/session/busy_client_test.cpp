// A client whose thread stands still in the middle of a level transfer (the desktop app's GUI thread in a long first
// paint on software GL, a slow or swapping machine) for longer than the host's sendStallTimeout: its TlsStream keeps
// taking the host's bytes on a thread of its own, so the host does not drop it as a peer that does not read, and the
// level arrives whole once the thread moves again; and its thread keeps turning while the password key (PBKDF2) is
// derived. The host runs on a thread of its own, as another process would.
#include "session/net/session_client.h"
#include "session/net/session_host.h"

#include <gtest/gtest.h>

#include <QtCore/QElapsedTimer>
#include <QtCore/QThread>
#include <QtCore/QTimer>
#include <QtTest/QTest>

#include "harmonic_host_model.h"
#include "raw_control_peer.h"
#include "session/wire/password_auth.h"
#include "test_meshes.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>
#include <utility>

namespace sc::session {
namespace {

using namespace std::chrono_literals;

/// A SessionHost made, run and destroyed on a thread of its own; run() executes a call there and waits for it.
class HostOnItsOwnThread {
 public:
  HostOnItsOwnThread(std::shared_ptr<const HostModel> model, SessionHostOptions options) {
    m_thread.start();
    m_context.moveToThread(&m_thread);
    run([&] {
      m_host = std::make_unique<SessionHost>(std::move(model), std::move(options));
      m_started = m_host->start(&m_error);
      m_port = m_host->tcpPort();
    });
  }
  ~HostOnItsOwnThread() {
    run([&] { m_host.reset(); });
    m_thread.quit();
    m_thread.wait();
  }
  HostOnItsOwnThread(const HostOnItsOwnThread&) = delete;
  HostOnItsOwnThread& operator=(const HostOnItsOwnThread&) = delete;

  template <class Call>
  void run(Call call) {
    QMetaObject::invokeMethod(&m_context, std::move(call), Qt::BlockingQueuedConnection);
  }
  [[nodiscard]] SessionHostCounters counters() {
    SessionHostCounters counters;
    run([&] { counters = m_host->counters(); });
    return counters;
  }

  bool m_started = false;
  QString m_error;
  quint16 m_port = 0;

 private:
  QThread m_thread;
  QObject m_context;  // lives on m_thread: the target of run()
  std::unique_ptr<SessionHost> m_host;
};

/// 127.0.0.1, any port, named "host", dropping a peer whose queue has not drained for 0.5 s (sendStallTimeout).
SessionHostOptions loopbackHostOptions() {
  SessionHostOptions options;
  options.address = QHostAddress::LocalHost;
  options.hostName = QStringLiteral("host");
  options.sendStallTimeout = 500ms;
  return options;
}

/// A client of 127.0.0.1:`port` named `name`, SessionClientOptions' defaults otherwise.
SessionClientOptions clientOptions(quint16 port, const QString& name) {
  SessionClientOptions options;
  options.port = port;
  options.name = name;
  return options;
}

TEST(BusyClient, AClientWhoseThreadStandsStillMidTransferKeepsReceivingAndIsNotDropped) {
  // icosphere(6) with m = 200 random columns: an incompressible payload of about 2 · 40962 · 200 bytes = 16 MB, more
  // than the kernel's buffers on loopback hold (both ends autotune to a few MB), so a client that does not read
  // stalls the host's queue.
  const std::shared_ptr<const HostModel> model = testing::incompressibleHostModel(sc::testing::icosphere(6), 200, 29);
  SessionHostOptions hostOptions = loopbackHostOptions();
  HostOnItsOwnThread host(model, std::move(hostOptions));
  ASSERT_TRUE(host.m_started) << host.m_error.toStdString();

  SessionClientOptions options = clientOptions(host.m_port, QStringLiteral("busy"));
  SessionClient client(std::move(options));
  quint64 received = 0;
  quint64 total = 0;
  QObject::connect(&client, &SessionClient::modelProgress, [&](quint64 r, quint64 t) {
    received = r;
    total = t;
  });
  client.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return received > 0 || client.state() >= SessionClient::State::Ready; }, 20000))
      << client.errorText().toStdString();
  ASSERT_EQ(client.state(), SessionClient::State::Loading) << "the transfer ended before the test could stall it";
  ASSERT_GT(total, 12u << 20);

  std::this_thread::sleep_for(2500ms);  // the client's thread stands still: five times the host's stall timeout

  ASSERT_TRUE(QTest::qWaitFor([&] { return client.state() >= SessionClient::State::Ready; }, 30000));
  EXPECT_EQ(client.state(), SessionClient::State::Ready) << client.errorText().toStdString();
  EXPECT_EQ(client.levelVertexCount(), static_cast<std::uint32_t>(model->vertexCount()));
  EXPECT_GE(client.streamBytesRead(), total);
  const SessionHostCounters counters = host.counters();
  EXPECT_EQ(counters.slowPeersDropped, 0u);
  EXPECT_EQ(counters.transfersCompleted, 1u);
}

TEST(BusyClient, APeerThatReadsNothingMidTransferIsDroppedAtTheStallTimeoutAndOthersJoin) {
  // The contrast to the test above, and the stall rule over real sockets: a peer made on this thread (which then
  // sleeps, so the peer reads nothing at all) with a 4 KiB receive window asks for a 7.4 MB level.
  const std::shared_ptr<const HostModel> model = testing::incompressibleHostModel(sc::testing::icosphere(6), 64, 31);
  SessionHostOptions hostOptions = loopbackHostOptions();
  HostOnItsOwnThread host(model, std::move(hostOptions));
  ASSERT_TRUE(host.m_started) << host.m_error.toStdString();

  testing::RawControlPeer hung(host.m_port, 4096);
  ASSERT_TRUE(hung.join(QStringLiteral("hung")).has_value());
  hung.send(ResolutionRequest{0});
  QTest::qWait(100);  // the request leaves
  std::this_thread::sleep_for(2000ms);
  SessionHostCounters counters = host.counters();
  EXPECT_EQ(counters.slowPeersDropped, 1u) << "the host dropped the peer that read nothing";
  EXPECT_EQ(counters.transfersCompleted, 0u);

  SessionClientOptions options = clientOptions(host.m_port, QStringLiteral("next"));
  SessionClient next(std::move(options));
  next.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return next.state() >= SessionClient::State::Ready; }, 20000));
  EXPECT_EQ(next.state(), SessionClient::State::Ready) << next.errorText().toStdString();
  counters = host.counters();
  EXPECT_EQ(counters.transfersCompleted, 1u);
  EXPECT_EQ(counters.slowPeersDropped, 1u);
}

TEST(BusyClient, TheClientsEventLoopTurnsWhileItDerivesThePasswordKey) {
  // The host asks for the most PBKDF2 iterations a client answers (1,000,000; the default is 600,000): the client's
  // key takes 0.25-0.6 s here, on a thread of its own; the client's thread meanwhile serves a 10 ms timer.
  constexpr std::uint32_t kIterations = kMaxPbkdf2Iterations;
  QElapsedTimer clock;
  clock.start();
  (void)derivePasswordKey(QStringLiteral("reference"), QByteArray(kSaltSize, 's'), kIterations);
  const qint64 derivationMs = clock.elapsed();  // what the key costs on this machine, now

  const std::shared_ptr<const HostModel> model = testing::incompressibleHostModel(sc::testing::icosphere(2), 20, 3);
  SessionHostOptions hostOptions = loopbackHostOptions();
  hostOptions.password = QStringLiteral("open sesame");
  hostOptions.pbkdf2Iterations = kIterations;
  HostOnItsOwnThread host(model, std::move(hostOptions));
  ASSERT_TRUE(host.m_started) << host.m_error.toStdString();

  SessionClientOptions options = clientOptions(host.m_port, QStringLiteral("patient"));
  options.password = QStringLiteral("open sesame");
  SessionClient client(std::move(options));
  qint64 longestGapMs = 0;
  qint64 lastTick = 0;
  QTimer ticker;
  QObject::connect(&ticker, &QTimer::timeout, [&] {
    const qint64 now = clock.elapsed();
    longestGapMs = std::max(longestGapMs, now - lastTick);
    lastTick = now;
  });
  lastTick = clock.elapsed();
  ticker.start(10);
  client.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return client.state() >= SessionClient::State::Ready; }, 20000));
  EXPECT_EQ(client.state(), SessionClient::State::Ready) << client.errorText().toStdString();
  EXPECT_GT(derivationMs, 100) << "the key must cost enough for the test to see a stall";
  EXPECT_LT(longestGapMs, derivationMs * 6 / 10)
      << "the client's thread stood still for " << longestGapMs << " ms; the key takes " << derivationMs << " ms";
}

}  // namespace
}  // namespace sc::session
