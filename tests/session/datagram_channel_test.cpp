// Tests src/session/host_datagram_channel.cpp and client_datagram_channel.cpp over real UDP sockets on 127.0.0.1:
// path opening, frame delivery within quantisation, byte counts, loss through the impairment layer, drops by
// reason on both sides (a replayed PathOpen moves no path; NAT rebinding still does), seeding from a keyframe and
// one-way latency. Needs the QCoreApplication of socket_test_main.cpp.
#include "session/client_datagram_channel.h"
#include "session/coefficient_codec.h"
#include "session/host_datagram_channel.h"
#include "session/path_open.h"
#include "session/session_clock.h"

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>
#include <QtCore/QDeadlineTimer>
#include <QtCore/QEventLoop>
#include <QtCore/QTimer>
#include <QtNetwork/QUdpSocket>
#include <QtTest/QSignalSpy>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

namespace {

using namespace sc::session;

constexpr PeerId kPeer = 7;
constexpr int kM = 100;
const QHostAddress kLoopback(QHostAddress::LocalHost);

QByteArray bytesOf(char fill, int size) { return QByteArray(size, fill); }
const QByteArray kKey = bytesOf('k', kDatagramKeySize);
const QByteArray kToken = bytesOf('t', kPathTokenSize);

/// Runs the event loop until `done` or `timeoutMs`; blocks in the event loop (no busy wait), waking at least
/// every 5 ms to re-check.
bool waitUntil(const std::function<bool()>& done, int timeoutMs = 5000) {
  const QDeadlineTimer deadline(timeoutMs);
  QTimer wake;
  wake.start(5);
  while (!done()) {
    if (deadline.hasExpired()) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents | QEventLoop::WaitForMoreEvents);
  }
  return true;
}

/// Spectrum-like coefficients: decaying with the row, seeded.
Eigen::MatrixXd frameZ(unsigned seed, int m = kM) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd Z(m, 3);
  for (int k = 0; k < m; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = uniform(rng) / (1.0 + k);
  return Z;
}

/// A host and a client on loopback, the client's path open.
struct Session {
  explicit Session(ClientDatagramOptions options = {}) : client(std::move(options)) {
    QString error;
    EXPECT_TRUE(host.bind(kLoopback, 0, &error)) << error.toStdString();
    EXPECT_TRUE(client.bind(kLoopback, &error)) << error.toStdString();
    host.addPeer(kPeer, kKey, kToken);
  }
  bool open() {
    client.open(kLoopback, host.port(), kPeer, kKey, kToken, kM);
    return waitUntil([this] { return host.pathOpen(kPeer); });
  }
  /// Sends `frames` frames starting at `first`, in batches small enough for the socket buffers, and waits until
  /// the client has read every datagram sent.
  bool stream(std::uint32_t first, int frames, int batch = 25) {
    for (int f = 0; f < frames; f += batch) {
      for (int i = f; i < std::min(frames, f + batch); ++i) {
        const auto frame = first + static_cast<std::uint32_t>(i);
        host.sendFrame(frame, frameZ(frame), sessionNow());
      }
      const std::uint64_t sent = host.traffic(kPeer).datagramsSent;
      if (!waitUntil([&] { return client.datagramsRead() >= sent; })) return false;
    }
    return true;
  }

  HostDatagramChannel host;
  ClientDatagramChannel client;
};

/// A socket that is neither the host nor the client.
struct Stranger {
  Stranger() { EXPECT_TRUE(socket.bind(kLoopback, 0)); }
  void send(const QByteArray& bytes, quint16 port) { socket.writeDatagram(bytes, kLoopback, port); }
  QUdpSocket socket;
};

TEST(DatagramChannel, PathStaysClosedUntilAValidPathOpen) {
  Session s;
  EXPECT_FALSE(s.host.pathOpen(kPeer));
  s.host.sendFrame(1, frameZ(1), sessionNow());
  EXPECT_EQ(s.host.traffic(kPeer).datagramsSent, 0u);  // nowhere to send yet
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  ASSERT_TRUE(s.open());
  ASSERT_EQ(opened.count(), 1);
  EXPECT_EQ(opened.at(0).at(0).value<PeerId>(), kPeer);
  EXPECT_EQ(s.host.peerPort(kPeer), s.client.localPort());
  EXPECT_EQ(s.host.drops(PathOpenError::None), 1u);
  EXPECT_GE(s.client.pathOpensSent(), 1u);
}

TEST(DatagramChannel, DeliversFramesWithinQuantisation) {
  Session s;
  ASSERT_TRUE(s.open());
  EXPECT_EQ(s.client.pathOpenIntervalMs(), ClientDatagramChannel::kPathOpenIntervalMs);
  QSignalSpy updated(&s.client, &ClientDatagramChannel::frameUpdated);
  const Eigen::MatrixXd Z = frameZ(42);
  s.host.sendFrame(1, Z, sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }));
  EXPECT_TRUE(s.client.hasFrame());
  EXPECT_EQ(s.client.currentFrame(), 1u);
  EXPECT_EQ(s.client.framesApplied(), 1u);
  EXPECT_EQ(updated.count(), 2);                             // one per accepted datagram
  EXPECT_EQ(s.client.pathOpenIntervalMs(), kPathRefreshMs);  // frames flow: refresh only
  const Eigen::MatrixXd& got = s.client.coefficients();
  ASSERT_EQ(got.rows(), kM);
  ASSERT_EQ(got.cols(), 3);
  const int bandRows = CodecOptions{}.bandRows;
  for (int b = 0; b * bandRows < kM; ++b) {
    const int rows = std::min(bandRows, kM - b * bandRows);
    const double bandMax = Z.middleRows(b * bandRows, rows).cwiseAbs().maxCoeff();
    const double error = (got - Z).middleRows(b * bandRows, rows).cwiseAbs().maxCoeff();
    EXPECT_LE(error, 1e-4 * bandMax) << "band " << b;
  }

  // m = 100 with the default layout: 2 datagrams of 378 bytes, 756 bytes per frame; wire adds 28 B each.
  const HostDatagramChannel::PeerTraffic traffic = s.host.traffic(kPeer);
  EXPECT_EQ(traffic.datagramsSent, 2u);
  EXPECT_EQ(traffic.bytesSent, 756u);
  EXPECT_NEAR(traffic.payloadKbpsOut, 756 * 8 / 1000.0, 1e-9);
  EXPECT_NEAR(traffic.wireKbpsOut, (756 + 2 * 28) * 8 / 1000.0, 1e-9);
  const ReceiverReport report = s.client.peek(sessionNow());
  EXPECT_EQ(report.received, 2);
  EXPECT_NEAR(report.payloadKbps, 756 * 8 / 1000.0, 1e-9);
  EXPECT_NEAR(report.wireKbps, (756 + 2 * 28) * 8 / 1000.0, 1e-9);
  EXPECT_EQ(s.client.droppedDatagrams(), 0u);

  // The next frame replaces the first.
  const Eigen::MatrixXd Z2 = frameZ(43);
  s.host.sendFrame(2, Z2, sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 4; }));
  EXPECT_EQ(s.client.currentFrame(), 2u);
  EXPECT_EQ(s.client.framesApplied(), 2u);
  EXPECT_LE((s.client.coefficients() - Z2).cwiseAbs().maxCoeff(), 1e-4 * Z2.cwiseAbs().maxCoeff());
}

TEST(DatagramChannel, ExtrapolateShowsOverdueFramesThenWithdrawsThem) {
  ClientDatagramOptions options;
  options.concealment = Concealment::Extrapolate;
  Session s(options);
  ASSERT_TRUE(s.open());
  ASSERT_NE(s.client.predictor(), nullptr);
  std::vector<std::uint32_t> shown;
  std::vector<std::uint32_t> withdrawn;
  QObject::connect(&s.client, &ClientDatagramChannel::frameUpdated, &s.client,
                   [&shown](std::uint32_t frame) { shown.push_back(frame); });
  QObject::connect(&s.client, &ClientDatagramChannel::predictionWithdrawn, &s.client,
                   [&withdrawn](std::uint32_t frame) { withdrawn.push_back(frame); });
  // A handle moving at constant velocity, 30 ms per frame; then the stream stops (the drag paused).
  const auto linear = [](std::uint32_t f) { return Eigen::MatrixXd(frameZ(1) * (1.0 + 0.05 * f)); };
  for (std::uint32_t f = 1; f <= 6; ++f) {
    s.host.sendFrame(f, linear(f), sessionNow());
    ASSERT_TRUE(waitUntil([&] { return s.client.receivedFrame() == f && s.client.assembler()->accepted() == 2 * f; }));
    waitUntil([] { return false; }, 30);
  }
  EXPECT_GT(s.client.predictor()->interval().count(), 0);
  ASSERT_TRUE(waitUntil([&] { return !withdrawn.empty(); }, 3000));
  EXPECT_EQ(withdrawn, std::vector<std::uint32_t>{6});
  EXPECT_GE(s.client.predictor()->framesPredicted(), 4u);  // maxFrames after the last frame
  // Frames 7..10 were shown (predicted) before the withdrawal; then frame 6 again.
  for (std::uint32_t f = 7; f <= 10; ++f) EXPECT_NE(std::find(shown.begin(), shown.end(), f), shown.end()) << f;
  EXPECT_EQ(shown.back(), 6u);
  EXPECT_EQ(s.client.currentFrame(), 6u);
  EXPECT_EQ(s.client.receivedFrame(), 6u);
  EXPECT_LE((s.client.coefficients() - linear(6)).cwiseAbs().maxCoeff(), 2e-4);
  // A real frame after the pause is shown as it is.
  s.host.sendFrame(7, linear(20), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.receivedFrame() == 7u && s.client.assembler()->accepted() == 14; }));
  EXPECT_EQ(s.client.currentFrame(), 7u);
  EXPECT_LE((s.client.coefficients() - linear(20)).cwiseAbs().maxCoeff(), 5e-4);
}

/// Rebinds the client's socket to another local port while its channel stays open (NAT rebinding: the same
/// client, its PathOpen count going on, now seen from a new port). Returns the new port (0 on failure).
quint16 rebind(ClientDatagramChannel& client) {
  const quint16 old = client.localPort();
  for (int attempt = 0; attempt < 8; ++attempt) {
    if (!client.bind(kLoopback, nullptr)) return 0;
    if (client.localPort() != old) return client.localPort();
  }
  return 0;
}

TEST(DatagramChannel, PathFollowsTheClientToANewAddress) {
  Session s;
  ASSERT_TRUE(s.open());
  const quint16 before = s.client.localPort();
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  const quint16 after = rebind(s.client);
  ASSERT_NE(after, 0);
  ASSERT_NE(after, before);
  // The client's next PathOpen (a higher sequence) moves the path.
  ASSERT_TRUE(waitUntil([&] { return s.host.peerPort(kPeer) == after; }));
  EXPECT_EQ(opened.count(), 1);
  EXPECT_EQ(s.host.drops(PathOpenError::Replayed), 0u);
  s.host.sendFrame(1, frameZ(1), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }));
  s.client.close();
  EXPECT_EQ(s.client.pathOpenIntervalMs(), 0);  // closed
  s.host.removePeer(kPeer);
  EXPECT_FALSE(s.host.pathOpen(kPeer));
}

TEST(DatagramChannel, ReplayedPathOpenDoesNotMoveThePath) {
  Session s;
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::None) >= 1; }));
  QSignalSpy opened(&s.host, &HostDatagramChannel::pathOpened);
  // What an eavesdropper recorded: the client's first PathOpen (encoding is deterministic, so these are its exact
  // bytes) and the latest one the host accepted (on loopback every one is accepted, in order).
  const auto peer = static_cast<std::uint16_t>(kPeer);
  const QByteArray first = encodePathOpen(peer, kToken, 1, kKey);
  const auto latestSequence = static_cast<std::uint32_t>(s.host.drops(PathOpenError::None));
  const QByteArray latest = encodePathOpen(peer, kToken, latestSequence, kKey);

  Stranger attacker;
  attacker.send(first, s.host.port());
  attacker.send(latest, s.host.port());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::Replayed) == 2; }));
  EXPECT_EQ(opened.count(), 0);
  EXPECT_EQ(s.host.peerAddress(kPeer), kLoopback);
  EXPECT_EQ(s.host.peerPort(kPeer), s.client.localPort());  // the path stayed with the client

  // NAT rebinding still works: the client's next (fresh) PathOpen from a new port moves the path. (Before any
  // frame, so the client still sends every kPathOpenIntervalMs.)
  const quint16 after = rebind(s.client);
  ASSERT_NE(after, 0);
  ASSERT_TRUE(waitUntil([&] { return s.host.peerPort(kPeer) == after; }));
  EXPECT_EQ(opened.count(), 1);
  EXPECT_EQ(s.host.drops(PathOpenError::Replayed), 2u);

  // The attacker replays again, now from its socket to the moved path: still nothing moves. Frames go to the
  // client, none to the attacker.
  attacker.send(latest, s.host.port());
  ASSERT_TRUE(waitUntil([&] { return s.host.drops(PathOpenError::Replayed) == 3; }));
  EXPECT_EQ(s.host.peerPort(kPeer), after);
  s.host.sendFrame(1, frameZ(1), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }));
  EXPECT_FALSE(attacker.socket.hasPendingDatagrams());
  EXPECT_EQ(opened.count(), 1);
}

TEST(DatagramChannel, SeedFromKeyframeThenNewerFramesOnly) {
  Session s;
  const Eigen::MatrixXd exact = frameZ(5);
  s.client.seed(5, exact);  // before open: kept, applied by open()
  ASSERT_TRUE(s.open());
  EXPECT_TRUE(s.client.hasFrame());
  EXPECT_EQ(s.client.currentFrame(), 5u);
  EXPECT_EQ(s.client.coefficients(), exact);  // exact, not quantised

  s.host.sendFrame(5, frameZ(5), sessionNow());  // frames <= the keyframe's are stale
  ASSERT_TRUE(waitUntil([&] { return s.client.datagramsRead() == 2; }));
  EXPECT_EQ(s.client.assembler()->assemblyDrops(AssemblyDrop::Late), 2u);
  EXPECT_EQ(s.client.coefficients(), exact);
  EXPECT_EQ(s.client.peek(sessionNow()).received, 2);  // authenticated: counted as arrived

  s.host.sendFrame(6, frameZ(6), sessionNow());
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }));
  EXPECT_EQ(s.client.currentFrame(), 6u);
  EXPECT_EQ(s.client.framesApplied(), 1u);
  s.client.seed(9, exact);  // ignored once a frame arrived
  EXPECT_EQ(s.client.currentFrame(), 6u);
}

TEST(DatagramChannel, ClientDropsBadDatagramsByReason) {
  Session s;
  ASSERT_TRUE(s.open());
  const quint16 port = s.client.localPort();
  Stranger stranger;
  std::uint64_t sent = 0;
  const auto send = [&](const QByteArray& bytes) {
    stranger.send(bytes, port);
    ++sent;
  };

  // A captured datagram (same key, sequence 0, frame 1): accepted from any source (the tag is the check), then
  // its replay is dropped.
  CoefficientEncoder sameKey(kKey, static_cast<std::uint16_t>(kPeer));
  const std::vector<QByteArray> captured = sameKey.encodeFrame(1, frameZ(1), wireTimestamp(sessionNow()));
  send(captured[0]);
  send(captured[0]);
  // Another key (a stranger who does not know ours).
  CoefficientEncoder otherKey(bytesOf('x', kDatagramKeySize), static_cast<std::uint16_t>(kPeer));
  otherKey.setNextSequence(10);
  send(otherKey.encodeFrame(2, frameZ(2))[0]);
  // Truncated: below the minimum size, and a cut that moves the tag.
  send(captured[1].left(kDatagramMinSize - 1));
  send(captured[1].left(captured[1].size() - 1));
  send(QByteArray());
  // Random garbage.
  std::mt19937 rng(3);
  QByteArray garbage(300, '\0');
  for (char& c : garbage) c = static_cast<char>(rng());
  send(garbage);
  ASSERT_TRUE(waitUntil([&] { return s.client.datagramsRead() == sent; }));

  const FrameAssembler& a = *s.client.assembler();
  EXPECT_EQ(a.accepted(), 1u);
  EXPECT_EQ(a.decodeDrops(DecodeError::Replayed), 1u);
  EXPECT_EQ(a.decodeDrops(DecodeError::BadTag), 3u);  // other key, tag moved by the cut, garbage
  EXPECT_EQ(a.decodeDrops(DecodeError::Truncated), 2u);
  EXPECT_EQ(s.client.droppedDatagrams(), 6u);
  EXPECT_EQ(s.client.peek(sessionNow()).received, 1);  // only authenticated datagrams reach the statistics

  // A frame older than the current one (authenticated, fresh sequence number) is Late.
  sameKey.setNextSequence(20);
  send(sameKey.encodeFrame(0, frameZ(0))[0]);
  ASSERT_TRUE(waitUntil([&] { return s.client.datagramsRead() == sent; }));
  EXPECT_EQ(a.assemblyDrops(AssemblyDrop::Late), 1u);
  EXPECT_EQ(s.client.droppedDatagrams(), 7u);
  EXPECT_EQ(s.client.currentFrame(), 1u);
}

TEST(DatagramChannel, ClientCountsDatagramsWhileClosed) {
  ClientDatagramChannel client;
  ASSERT_TRUE(client.bind(kLoopback, nullptr));
  EXPECT_EQ(client.assembler(), nullptr);
  EXPECT_EQ(client.coefficients().rows(), 0);
  Stranger stranger;
  stranger.send(QByteArray("early"), client.localPort());
  ASSERT_TRUE(waitUntil([&] { return client.datagramsRead() == 1; }));
  EXPECT_EQ(client.droppedDatagrams(), 1u);
  EXPECT_FALSE(client.hasFrame());
}

TEST(DatagramChannel, HostDropsBadPathOpensByReason) {
  HostDatagramChannel host;
  ASSERT_TRUE(host.bind(kLoopback, 0, nullptr));
  host.addPeer(kPeer, kKey, kToken);
  Stranger stranger;
  const std::uint16_t peer = static_cast<std::uint16_t>(kPeer);
  const QByteArray valid = encodePathOpen(peer, kToken, 5, kKey);
  std::mt19937 rng(11);
  QByteArray random(kPathOpenSize + 20, '\0');
  for (char& c : random) c = static_cast<char>(rng());
  QByteArray forged = valid;  // right length and peer id, random rest
  for (int i = 6; i < forged.size(); ++i) forged[i] = static_cast<char>(rng());
  const auto totalDrops = [&] {
    std::uint64_t total = 0;
    for (int r = 0; r < static_cast<int>(PathOpenError::Count); ++r) total += host.drops(static_cast<PathOpenError>(r));
    return total;
  };

  stranger.send(random, host.port());                                                           // Truncated (length)
  stranger.send(valid.left(kPathOpenSize - 1), host.port());                                    // Truncated
  stranger.send(encodePathOpen(peer, bytesOf('w', kPathTokenSize), 5, kKey), host.port());      // Stranger (token)
  stranger.send(encodePathOpen(99, kToken, 5, kKey), host.port());                              // Stranger (peer)
  stranger.send(encodePathOpen(peer, kToken, 5, bytesOf('x', kDatagramKeySize)), host.port());  // BadTag
  stranger.send(forged, host.port());                                                           // BadTag
  stranger.send(encodePathOpen(peer, kToken, 0, kKey), host.port());  // Replayed (0 is never above the highest)
  ASSERT_TRUE(waitUntil([&] { return totalDrops() == 7; }));
  EXPECT_EQ(host.drops(PathOpenError::Truncated), 2u);
  EXPECT_EQ(host.drops(PathOpenError::Stranger), 2u);
  EXPECT_EQ(host.drops(PathOpenError::BadTag), 2u);
  EXPECT_EQ(host.drops(PathOpenError::Replayed), 1u);
  EXPECT_EQ(host.drops(PathOpenError::None), 0u);
  EXPECT_FALSE(host.pathOpen(kPeer));

  // Sequences need not be consecutive, only increasing: 5 opens; 5 again and 3 are replays; 6 is fresh.
  QSignalSpy opened(&host, &HostDatagramChannel::pathOpened);
  stranger.send(valid, host.port());
  stranger.send(valid, host.port());
  stranger.send(encodePathOpen(peer, kToken, 3, kKey), host.port());
  stranger.send(encodePathOpen(peer, kToken, 6, kKey), host.port());
  ASSERT_TRUE(waitUntil([&] { return totalDrops() == 11; }));
  EXPECT_EQ(host.drops(PathOpenError::None), 2u);
  EXPECT_EQ(host.drops(PathOpenError::Replayed), 3u);
  EXPECT_TRUE(host.pathOpen(kPeer));
  EXPECT_EQ(host.peerPort(kPeer), stranger.socket.localPort());
  EXPECT_EQ(opened.count(), 1);  // the same address twice: one signal

  // Re-adding the peer (a new Welcome) forgets its highest sequence: the client starts again at 1.
  host.addPeer(kPeer, kKey, kToken);
  EXPECT_FALSE(host.pathOpen(kPeer));
  stranger.send(encodePathOpen(peer, kToken, 1, kKey), host.port());
  ASSERT_TRUE(waitUntil([&] { return host.drops(PathOpenError::None) == 3; }));
  EXPECT_TRUE(host.pathOpen(kPeer));
  EXPECT_EQ(host.drops(PathOpenError::Replayed), 3u);

  // A removed peer's PathOpen is a stranger's.
  host.removePeer(kPeer);
  stranger.send(encodePathOpen(peer, kToken, 2, kKey), host.port());
  ASSERT_TRUE(waitUntil([&] { return host.drops(PathOpenError::Stranger) == 3; }));
  EXPECT_FALSE(host.pathOpen(kPeer));
}

/// Loss measured by the receiver statistics over 5000 real datagrams vs the impairment's setting.
void expectMeasuredLoss(const ImpairmentSettings& settings) {
  ClientDatagramOptions options;
  options.impairment = settings;
  Session s(options);
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(s.stream(1, 2500));  // 2 datagrams per frame
  const NetworkImpairment& impairment = *s.client.impairment();
  ASSERT_EQ(impairment.offered(), 5000u);                              // no loss on the real socket
  ASSERT_TRUE(waitUntil([&] { return impairment.inFlight() == 0; }));  // nothing held back
  const ReceiverReport report = s.client.report(sessionNow());
  const double simulated = static_cast<double>(impairment.dropped()) / 5000.0;
  EXPECT_NEAR(report.lossFraction, settings.loss, 0.02);
  // The statistics see exactly what the impairment dropped (up to losses at the very ends of the run).
  EXPECT_NEAR(report.lossFraction, simulated, 0.002);
  EXPECT_EQ(s.client.assembler()->accepted() + impairment.dropped(), 5000u);
  EXPECT_EQ(s.client.droppedDatagrams(), 0u);
}

TEST(DatagramChannel, MeasuredBernoulliLossMatchesSetting) {
  ImpairmentSettings settings;
  settings.loss = 0.2;
  settings.seed = 2024;
  expectMeasuredLoss(settings);
}

TEST(DatagramChannel, MeasuredBurstLossMatchesSetting) {
  ImpairmentSettings settings;
  settings.loss = 0.2;
  settings.burst = true;
  settings.burstLength = 3.0;
  settings.seed = 2025;
  expectMeasuredLoss(settings);
}

TEST(DatagramChannel, LatencyOnLoopbackIsSmall) {
  Session s;
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(s.stream(1, 100, 5));
  const ReceiverReport report = s.client.report(sessionNow());
  EXPECT_EQ(report.received, 200);
  EXPECT_EQ(report.cumulativeLost, 0);
  EXPECT_GE(report.latencyP50Ms, 0.0);
  EXPECT_LT(report.latencyP99Ms, 50.0);
  EXPECT_TRUE(std::isfinite(report.jitterMs));
}

TEST(DatagramChannel, ImpairmentDelayIsAppliedByThePreciseTimer) {
  ClientDatagramOptions options;
  options.impairment = ImpairmentSettings{};
  options.impairment->delay = Millis{30};
  Session s(options);
  ASSERT_TRUE(s.open());
  const Micros sentAt = sessionNow();
  s.host.sendFrame(1, frameZ(1), sentAt);
  ASSERT_TRUE(waitUntil([&] { return s.client.datagramsRead() == 2; }));
  EXPECT_EQ(s.client.assembler()->accepted(), 0u);  // held back
  ASSERT_TRUE(waitUntil([&] { return s.client.assembler()->accepted() == 2; }, 2000));
  EXPECT_GE((sessionNow() - sentAt).count(), 29'000);
  const ReceiverReport report = s.client.report(sessionNow());
  EXPECT_GE(report.latencyP50Ms, 29.0);
  EXPECT_LT(report.latencyP99Ms, 30.0 + 50.0);
}

TEST(DatagramChannel, ImpairmentChangesLiveWhileOpen) {
  Session s;  // no impairment at first
  ASSERT_TRUE(s.open());
  ASSERT_TRUE(s.stream(1, 500));
  EXPECT_EQ(s.client.impairment(), nullptr);
  ReceiverReport report = s.client.report(sessionNow());
  EXPECT_EQ(report.received, 1000);
  EXPECT_NEAR(report.intervalLossFraction, 0.0, 1e-12);

  // 30% Bernoulli loss, switched on while open: the next interval measures it.
  ImpairmentSettings lossy;
  lossy.loss = 0.3;
  lossy.seed = 77;
  s.client.setImpairment(lossy);
  ASSERT_NE(s.client.impairment(), nullptr);
  ASSERT_TRUE(s.client.impairmentSettings().has_value());
  ASSERT_TRUE(s.stream(501, 1500));
  ASSERT_TRUE(waitUntil([&] { return s.client.impairment()->inFlight() == 0; }));
  report = s.client.report(sessionNow());
  EXPECT_NEAR(report.intervalLossFraction, 0.3, 0.03);
  EXPECT_EQ(s.client.impairment()->offered(), 3000u);

  // A delayed impairment holding datagrams is replaced: what it held is delivered at once, nothing is lost.
  ImpairmentSettings delayed;
  delayed.delay = Millis{400};
  s.client.setImpairment(delayed);
  const std::uint64_t acceptedBefore = s.client.assembler()->accepted();
  ASSERT_TRUE(s.stream(2001, 10));
  EXPECT_EQ(s.client.impairment()->inFlight(), 20u);
  EXPECT_EQ(s.client.assembler()->accepted(), acceptedBefore);
  s.client.setImpairment(std::nullopt);
  EXPECT_EQ(s.client.impairment(), nullptr);
  EXPECT_EQ(s.client.assembler()->accepted(), acceptedBefore + 20);

  // Back to no impairment: no loss again.
  (void)s.client.report(sessionNow());
  ASSERT_TRUE(s.stream(2011, 500));
  report = s.client.report(sessionNow());
  EXPECT_NEAR(report.intervalLossFraction, 0.0, 1e-12);
  EXPECT_EQ(s.client.droppedDatagrams(), 0u);
}

TEST(DatagramChannel, ImpairmentSetBeforeOpenIsUsedByOpen) {
  Session s;
  ImpairmentSettings lossy;
  lossy.loss = 0.5;
  s.client.setImpairment(lossy);
  EXPECT_EQ(s.client.impairment(), nullptr);  // not open yet
  ASSERT_TRUE(s.open());
  ASSERT_NE(s.client.impairment(), nullptr);
  EXPECT_DOUBLE_EQ(s.client.impairment()->settings().loss, 0.5);
}

}  // namespace
