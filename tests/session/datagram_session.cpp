#include "datagram_session.h"

#include "session/engine/session_clock.h"

#include <gtest/gtest.h>

#include <QtCore/QCoreApplication>
#include <QtCore/QDeadlineTimer>
#include <QtCore/QEventLoop>
#include <QtCore/QTimer>

#include <QtNetwork/QNetworkDatagram>

#include <algorithm>
#include <optional>
#include <random>
#include <utility>

namespace sc::session::testing {

bool waitUntil(const std::function<bool()>& done, int timeoutMs) {
  const QDeadlineTimer deadline(timeoutMs);
  QTimer wake;
  wake.start(5);
  while (!done()) {
    if (deadline.hasExpired()) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents | QEventLoop::WaitForMoreEvents);
  }
  return true;
}

Eigen::MatrixXd frameZ(unsigned seed, int m) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd Z(m, 3);
  for (int k = 0; k < m; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = uniform(rng) / (1.0 + k);
  return Z;
}

Session::Session(ClientDatagramOptions options) : client(std::move(options)) {
  QString error;
  EXPECT_TRUE(host.bind(kLoopback, 0, &error)) << error.toStdString();
  EXPECT_TRUE(client.bind(kLoopback, &error)) << error.toStdString();
  host.addPeer(kPeer, kKey, kToken);
}

bool Session::open() {
  client.open(kLoopback, host.port(), kPeer, kKey, kToken, kM);
  return waitUntil([this] { return host.pathOpen(kPeer); });
}

bool Session::stream(std::uint32_t first, int frames, int batch) {
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

Stranger::Stranger() { EXPECT_TRUE(socket.bind(kLoopback, 0)); }

void Stranger::send(const QByteArray& bytes, quint16 port) { socket.writeDatagram(bytes, kLoopback, port); }

bool Stranger::answerChallenge(quint16 port) {
  const DatagramMac mac(kKey);
  std::optional<std::uint64_t> challenge;
  const bool answered = waitUntil([&] {
    while (socket.hasPendingDatagrams()) {  // the latest challenge counts (the host repeats it per PathOpen)
      const QByteArray bytes = socket.receiveDatagram().data();
      const PathProbeResult result = decodePathProbe(bytes, MessageType::PathChallenge, mac);
      if (result.error == PathOpenError::None) challenge = result.challenge;
    }
    return challenge.has_value();
  });
  if (!answered) return false;
  send(encodePathProbe(MessageType::PathResponse, static_cast<std::uint16_t>(kPeer), *challenge, mac), port);
  return true;
}

}  // namespace sc::session::testing
