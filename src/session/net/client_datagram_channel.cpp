#include "session/net/client_datagram_channel.h"

#include "session/engine/session_clock.h"
#include "session/net/host_datagram_channel.h"
#include "session/wire/path_open.h"

#include <QtCore/QTimer>
#include <QtCore/QVariant>
#include <QtNetwork/QNetworkDatagram>
#include <QtNetwork/QUdpSocket>

#include <algorithm>
#include <chrono>
#include <limits>
#include <utility>

namespace sc::session {
namespace {

Millis toMillis(Micros at) { return std::chrono::floor<Millis>(at); }

}  // namespace

ClientDatagramChannel::ClientDatagramChannel(ClientDatagramOptions options, QObject* parent)
    : QObject(parent),
      m_options(std::move(options)),
      m_socket(new QUdpSocket(this)),
      m_pathTimer(new QTimer(this)),
      m_releaseTimer(new QTimer(this)),
      m_predictTimer(new QTimer(this)),
      m_empty(0, 3) {
  connect(m_socket, &QUdpSocket::readyRead, this, &ClientDatagramChannel::readPending);
  connect(m_pathTimer, &QTimer::timeout, this, &ClientDatagramChannel::sendPathOpen);
  m_releaseTimer->setSingleShot(true);
  m_releaseTimer->setTimerType(Qt::PreciseTimer);
  connect(m_releaseTimer, &QTimer::timeout, this, &ClientDatagramChannel::releaseDue);
  m_predictTimer->setSingleShot(true);
  m_predictTimer->setTimerType(Qt::PreciseTimer);
  connect(m_predictTimer, &QTimer::timeout, this, &ClientDatagramChannel::predictDue);
}

ClientDatagramChannel::~ClientDatagramChannel() = default;

std::unique_ptr<NetworkImpairment> ClientDatagramChannel::makeImpairment() const {
  if (!m_options.impairment) return nullptr;
  return std::make_unique<NetworkImpairment>(*m_options.impairment, m_options.link);
}

bool ClientDatagramChannel::bind(const QHostAddress& local, QString* error) {
  if (m_socket->state() != QAbstractSocket::UnconnectedState) m_socket->close();
  if (!m_socket->bind(local, 0)) {
    if (error != nullptr) *error = m_socket->errorString();
    return false;
  }
  m_socket->setSocketOption(QAbstractSocket::ReceiveBufferSizeSocketOption, QVariant(1 << 20));
  return true;
}

quint16 ClientDatagramChannel::localPort() const { return m_socket->localPort(); }

void ClientDatagramChannel::open(const QHostAddress& host, quint16 udpPort, PeerId self, QByteArray key,
                                 QByteArray token, int m) {
  m = std::clamp(m, 1, kMaxRows);
  const auto peer = static_cast<std::uint16_t>(self);
  m_host = host;
  m_hostPort = udpPort;
  m_self = peer;
  m_key = key;
  m_mac = std::make_unique<DatagramMac>(key);
  m_token = std::move(token);
  m_pathSequence = 0;
  m_assembler = std::make_unique<FrameAssembler>(std::move(key), peer, m, m_options.concealment);
  m_predictor = m_options.concealment == Concealment::Extrapolate
                    ? std::make_unique<FramePredictor>(m, m_options.predictor)
                    : nullptr;
  m_predictTimer->stop();
  m_impairment = makeImpairment();
  m_statistics = std::make_unique<ReceiverStatistics>();
  m_releaseTimer->stop();
  m_framesApplied = 0;
  m_open = true;
  if (m_pendingSeed) {
    const auto [frame, Z] = std::move(*m_pendingSeed);
    m_pendingSeed.reset();
    seed(frame, Z);
  }
  sendPathOpen();
  m_pathTimer->start(kPathOpenIntervalMs);
}

void ClientDatagramChannel::setImpairment(std::optional<ImpairmentSettings> settings, std::shared_ptr<LinkRate> link) {
  m_options.impairment = std::move(settings);
  m_options.link = std::move(link);
  if (!m_open || !m_assembler) {
    m_impairment.reset();  // open() creates it from m_options
    m_releaseTimer->stop();
    return;
  }
  std::unique_ptr<NetworkImpairment> old = std::move(m_impairment);
  m_impairment = makeImpairment();
  m_releaseTimer->stop();
  if (old) {
    // Everything the old impairment still holds, in its release order (see the header).
    const Micros now = sessionNow();
    for (const QByteArray& bytes : old->popDue(Millis::max())) {
      process(bytes, now);
      if (!m_open || !m_assembler) return;  // a slot of frameUpdated closed the channel
    }
  }
  if (m_impairment) armReleaseTimer();
}

void ClientDatagramChannel::close() {
  m_open = false;
  m_pathTimer->stop();
  m_releaseTimer->stop();
  m_predictTimer->stop();
}

void ClientDatagramChannel::seed(std::uint32_t frame, const Eigen::MatrixXd& Z) {
  if (!m_assembler) {
    m_pendingSeed.emplace(frame, Z);
    return;
  }
  if (!m_assembler->seed(frame, Z)) return;
  if (m_predictor) {
    m_predictor->observe(*m_assembler, sessionNow());
    armPredictTimer();
  }
  emit frameUpdated(frame);
}

const Eigen::MatrixXd& ClientDatagramChannel::coefficients() const {
  if (m_predictor) return m_predictor->display();
  return m_assembler ? m_assembler->z() : m_empty;
}

std::uint32_t ClientDatagramChannel::currentFrame() const {
  if (m_predictor) return m_predictor->displayedFrame();
  return receivedFrame();
}

std::uint32_t ClientDatagramChannel::receivedFrame() const { return m_assembler ? m_assembler->frame() : 0; }

bool ClientDatagramChannel::hasFrame() const { return m_assembler && m_assembler->hasFrame(); }

ReceiverReport ClientDatagramChannel::report(Micros now) {
  return m_statistics ? m_statistics->report(now) : ReceiverReport{};
}

ReceiverReport ClientDatagramChannel::peek(Micros now) const {
  return m_statistics ? m_statistics->peek(now) : ReceiverReport{};
}

void ClientDatagramChannel::clearLatency() {
  if (m_statistics) m_statistics->clearLatency();
}

std::uint64_t ClientDatagramChannel::droppedDatagrams() const {
  return m_unopenedDrops + (m_assembler ? m_assembler->totalDrops() : 0);
}

int ClientDatagramChannel::pathOpenIntervalMs() const { return m_pathTimer->isActive() ? m_pathTimer->interval() : 0; }

void ClientDatagramChannel::sendPathOpen() {
  if (!m_open) return;
  // Never wraps (2^32 PathOpens at 500 ms each is 68 years): a wrapped sequence would be dropped as Replayed.
  if (m_pathSequence == std::numeric_limits<std::uint32_t>::max()) return;
  const QByteArray pathOpen = encodePathOpen(m_self, m_token, ++m_pathSequence, m_key);
  if (m_socket->writeDatagram(pathOpen, m_host, m_hostPort) == pathOpen.size()) ++m_pathOpensSent;
}

bool ClientDatagramChannel::answerPathChallenge(const QByteArray& bytes) {
  if (!looksLikePathProbe(bytes, MessageType::PathChallenge)) return false;
  if (!m_open || !m_mac || pathProbePeer(bytes) != m_self) return true;  // not ours: ignored
  const PathProbeResult result = decodePathProbe(bytes, MessageType::PathChallenge, *m_mac);
  if (result.error != PathOpenError::None) return true;
  const QByteArray response = encodePathProbe(MessageType::PathResponse, m_self, result.challenge, *m_mac);
  if (m_socket->writeDatagram(response, m_host, m_hostPort) == response.size()) ++m_pathChallengesAnswered;
  return true;
}

void ClientDatagramChannel::readPending() {
  bool queued = false;
  for (int read = 0; read < kMaxDatagramsPerPass && m_socket->hasPendingDatagrams(); ++read) {
    const QNetworkDatagram datagram = m_socket->receiveDatagram();
    if (!datagram.isValid()) break;  // a socket error (e.g. a pending ICMP report): nothing to read
    if (answerPathChallenge(datagram.data())) continue;
    ++m_datagramsRead;
    m_bytesRead += static_cast<std::uint64_t>(datagram.data().size());
    if (!m_open || !m_assembler) {
      ++m_unopenedDrops;
      continue;
    }
    const Micros now = sessionNow();
    if (m_impairment) {
      m_impairment->push(datagram.data(), toMillis(now));
      queued = true;
    } else {
      process(datagram.data(), now);
    }
  }
  if (queued) releaseDue();
  // More pending: the rest is read in a later pass. The socket notifier is level-triggered, so readyRead fires
  // again on the next pass, after the events that queued up meanwhile. Not a queued call of readPending(): reading
  // outside readyRead can leave QAbstractSocket's unbuffered read notifier disabled with data pending (measured:
  // the client then stalled with 400 datagrams unread).
}

void ClientDatagramChannel::releaseDue() {
  if (!m_impairment || !m_open) return;
  const Micros now = sessionNow();
  for (const QByteArray& bytes : m_impairment->popDue(toMillis(now))) {
    process(bytes, now);
    if (!m_impairment || !m_open) return;  // a slot of frameUpdated closed or re-opened the channel
  }
  armReleaseTimer();
}

void ClientDatagramChannel::armReleaseTimer() {
  const Millis due = m_impairment->nextDue();
  if (due == Millis::max()) {
    m_releaseTimer->stop();
    return;
  }
  const Millis wait = std::max(Millis{0}, due - toMillis(sessionNow()));
  m_releaseTimer->start(static_cast<int>(std::min<Millis::rep>(wait.count(), 1'000'000)));
}

void ClientDatagramChannel::process(const QByteArray& bytes, Micros now) {
  FrameAssembler& assembler = *m_assembler;
  const std::uint64_t authenticatedBefore = assembler.authenticated();
  const bool hadFrame = assembler.hasFrame();
  const std::uint32_t frameBefore = assembler.frame();
  const DecodeError error = assembler.receive(bytes);
  if (assembler.authenticated() != authenticatedBefore) {
    // Authenticated and fresh (applied, or dropped as Late / WrongLength): it arrived, for loss and jitter.
    const DatagramHeader& header = assembler.lastHeader();
    const auto size = static_cast<std::size_t>(bytes.size());
    m_statistics->record(header.sequence, unwrapTimestamp(header.timestamp, now), now, size, size + kUdpIpv4Overhead);
  }
  if (error != DecodeError::None) return;
  if (!hadFrame || assembler.frame() != frameBefore) {  // a new frame number: one more frame applied
    ++m_framesApplied;
    m_statistics->recordFrame(now);
  }
  if (m_pathTimer->interval() != kPathRefreshMs) m_pathTimer->start(kPathRefreshMs);  // frames flow: refresh only
  if (m_predictor) {
    m_predictor->observe(assembler, now);
    armPredictTimer();
  }
  emit frameUpdated(currentFrame());
}

void ClientDatagramChannel::armPredictTimer() {
  const std::optional<Micros> due = m_predictor ? m_predictor->nextDue() : std::nullopt;
  if (!due || !m_open) {
    m_predictTimer->stop();
    return;
  }
  // Rounded up to whole milliseconds (QTimer's unit): never early, at most 1 ms late.
  const Micros wait = std::max(Micros{0}, *due - sessionNow());
  m_predictTimer->start(static_cast<int>(std::min<Micros::rep>((wait.count() + 999) / 1000, 1'000'000)));
}

void ClientDatagramChannel::predictDue() {
  if (!m_predictor || !m_open) return;
  switch (m_predictor->advance(sessionNow())) {
    case FramePredictor::Step::None:
      break;
    case FramePredictor::Step::Predicted:
      emit frameUpdated(currentFrame());
      break;
    case FramePredictor::Step::Withdrawn:
      emit predictionWithdrawn(m_predictor->receivedFrame());
      emit frameUpdated(currentFrame());
      break;
  }
  if (m_predictor && m_open) armPredictTimer();  // a slot may have closed or re-opened the channel
}

}  // namespace sc::session
