// Tests frame delivery by src/session/net/host_datagram_channel.cpp and client_datagram_channel.cpp over real UDP
// sockets on 127.0.0.1: frames within quantisation and their byte counts, extrapolated overdue frames withdrawn,
// seeding from a keyframe, and the client's drops by reason (also while closed). Set-up: datagram_session.h.
#include "datagram_session.h"

#include "session/engine/session_clock.h"
#include "session/wire/coefficient_codec.h"

#include <gtest/gtest.h>

#include <QtTest/QSignalSpy>

#include <algorithm>
#include <cmath>

namespace {

using namespace sc::session;
using namespace sc::session::testing;

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

}  // namespace
