// SessionClient: connection, handshake, control messages, sending and the periodic timers. The level transfer's
// decode worker and the reconstruction of positions are in session_client_level.cpp.

#include "session/net/session_client.h"

#include "session/engine/session_clock.h"
#include "session/net/tls_identity.h"
#include "session/net/tls_known_hosts.h"
#include "session/net/tls_server.h"

#include <QtCore/QTimer>
#include <QtNetwork/QSslSocket>

#include <algorithm>
#include <cmath>

namespace sc::session {
namespace {

constexpr int kSecondMs = 1000;  ///< heartbeat, stats report and host-silence check
constexpr int kRenewPollMs = 250;

Millis nowMillis() { return std::chrono::duration_cast<Millis>(sessionNow()); }

/// StatsReport doubles must be finite and ≥ 0.
double figure(double value) { return std::isfinite(value) && value > 0.0 ? value : 0.0; }

QString describe(MessageType type) {
  return QStringLiteral("0x%1").arg(static_cast<int>(type), 2, 16, QLatin1Char('0'));
}

}  // namespace

SessionClient::SessionClient(SessionClientOptions options, QObject* parent)
    : QObject(parent),
      m_options(std::move(options)),
      m_handshake(ClientHandshakeConfig{m_options.name, m_options.password, {}}) {
  m_socket = new QSslSocket(this);
  m_socket->setSslConfiguration(clientTlsConfiguration());
  m_channel = new ClientDatagramChannel(ClientDatagramOptions{m_options.concealment, m_options.impairment, {}}, this);
  m_secondTimer = new QTimer(this);
  m_renewTimer = new QTimer(this);
  m_recomputeTimer = new QTimer(this);
  m_recomputeTimer->setSingleShot(true);
  m_recomputeTimer->setInterval(0);
  connect(m_socket, &QTcpSocket::connected, this,
          [this] { m_socket->setSocketOption(QAbstractSocket::LowDelayOption, 1); });
  connect(m_socket, &QSslSocket::encrypted, this, &SessionClient::onEncrypted);
  connect(m_socket, &QTcpSocket::readyRead, this, &SessionClient::readAvailable);
  connect(m_socket, &QTcpSocket::disconnected, this, [this] {
    if (m_handshake.state() == ClientHandshake::State::Refused) {
      fail(m_handshake.errorText());
    } else if (live()) {
      fail(QStringLiteral("host lost: the connection closed without a Leave"));
    } else {
      fail(QStringLiteral("the host closed the connection"));
    }
  });
  connect(m_socket, &QTcpSocket::errorOccurred, this, [this](QAbstractSocket::SocketError error) {
    if (error == QAbstractSocket::RemoteHostClosedError) return;  // disconnected() reports it
    fail(live() ? QStringLiteral("host lost: %1").arg(m_socket->errorString()) : m_socket->errorString());
  });
  connect(m_channel, &ClientDatagramChannel::frameUpdated, this, &SessionClient::onFrameUpdated);
  connect(m_recomputeTimer, &QTimer::timeout, this, [this] {
    if (m_positionsDirty) updatePositions();
  });
  connect(m_secondTimer, &QTimer::timeout, this, &SessionClient::everySecond);
  connect(m_renewTimer, &QTimer::timeout, this, &SessionClient::renewTick);
}

SessionClient::~SessionClient() {
  // A decode in flight only posts its result to this object (a queued call, discarded with the object's pending
  // events by ~QObject): wait for it here, before any member it could be racing with is gone.
  if (m_decoder.joinable()) m_decoder.join();
  disconnect(m_socket, nullptr, this, nullptr);
}

void SessionClient::start() {
  if (m_state != State::Idle) return;
  changeState(State::Connecting);
  m_socket->connectToHostEncrypted(m_options.host, m_options.port);
}

void SessionClient::onEncrypted() {
  const QByteArray presented = certificateFingerprint(m_socket->peerCertificate());
  m_hostFingerprint = presented;  // also when refused below: the UI shows what was seen
  KnownHosts known(m_options.knownHostsFile);
  const bool tofu = m_options.trustOnFirstUse;
  const FingerprintCheck check = checkFingerprint(
      presented, m_options.fingerprint, tofu ? known.lookup(m_options.host, m_options.port) : std::nullopt, tofu);
  if (!check.accepted()) {
    fail(check.reason);
    return;
  }
  using V = FingerprintCheck::Verdict;
  if (tofu && (check.verdict == V::FirstUse || check.verdict == V::Pinned)) {
    known.remember(m_options.host, m_options.port, presented);
  }
  m_handshake = ClientHandshake(ClientHandshakeConfig{m_options.name, m_options.password, presented});
  m_lastHeard = sessionNow();
  changeState(State::Handshaking);
  send(m_handshake.start());
}

void SessionClient::leave() {
  if (m_state == State::Idle || m_state == State::Left || m_state == State::Failed) return;
  if (live()) send(Leave{});  // during the handshake a Leave would be a protocol error: just close
  m_secondTimer->stop();
  m_renewTimer->stop();
  m_channel->close();
  m_errorText = QStringLiteral("left the session");
  changeState(State::Left);
  m_socket->disconnectFromHost();  // writes the Leave first
}

void SessionClient::changeState(State next) {
  if (next == m_state) return;
  m_state = next;
  emit stateChanged(next);
}

void SessionClient::fail(const QString& reason) {
  if (m_state == State::Left || m_state == State::Failed) return;
  m_errorText = reason;
  m_secondTimer->stop();
  m_renewTimer->stop();
  m_channel->close();
  changeState(State::Failed);
  m_socket->abort();
  emit failed(reason);
}

void SessionClient::send(const ControlMessage& message) {
  if (m_socket->state() != QAbstractSocket::ConnectedState) return;
  const QByteArray frame = encodeControlMessage(message);
  if (!frame.isEmpty()) m_socket->write(frame);
}

void SessionClient::sendLock(const std::optional<LockMessage>& message) {
  if (message) send(*message);
}

// --- receiving

void SessionClient::readAvailable() {
  const QByteArray bytes = m_socket->readAll();
  if (bytes.isEmpty()) return;
  m_lastHeard = sessionNow();
  m_reader.append(bytes);
  while (m_state == State::Handshaking || live()) {
    std::optional<ControlDecodeResult> result = m_reader.next();
    if (!result) break;
    if (m_state == State::Handshaking) {
      handleHandshake(result->error == ControlError::None ? m_handshake.handleMessage(result->message)
                                                          : m_handshake.handleDecodeError(result->error));
    } else if (result->error != ControlError::None) {
      fail(QStringLiteral("protocol error from the host: %1").arg(QString::fromLatin1(toString(result->error))));
    } else {
      onMessage(result->message);
    }
  }
}

void SessionClient::handleHandshake(const HandshakeOutput& out) {
  for (const ControlMessage& message : out.send) send(message);
  if (m_handshake.state() == ClientHandshake::State::Refused) {
    fail(m_handshake.errorText());
  } else if (m_handshake.state() == ClientHandshake::State::Joined) {
    onJoined();
  }
}

void SessionClient::onJoined() {
  m_session = m_handshake.session();
  m_lock = std::make_unique<LockClient>(m_session->peerId);
  QHostAddress host = m_socket->peerAddress();
  bool ipv4 = false;
  const quint32 v4 = host.toIPv4Address(&ipv4);
  if (ipv4) host = QHostAddress(v4);
  QString error;
  if (!m_channel->bind(QHostAddress(ipv4 ? QHostAddress::AnyIPv4 : QHostAddress::AnyIPv6), &error)) {
    fail(QStringLiteral("UDP bind failed: %1").arg(error));
    return;
  }
  m_channel->open(host, m_session->udpPort, m_session->peerId, m_session->datagramKey, m_session->pathToken,
                  m_session->rowCount);
  changeState(State::Loading);
  if (m_options.levelFraction) {
    const double fraction = *m_options.levelFraction;
    const double wanted = fraction >= 1.0 || !(fraction > 0.0) ? 0.0 : std::round(fraction * m_session->vertexCount);
    m_options.level = static_cast<std::uint32_t>(std::max(0.0, wanted));
  }
  send(ResolutionRequest{m_options.level});
  m_secondTimer->start(kSecondMs);
  m_renewTimer->start(kRenewPollMs);
}

void SessionClient::onMessage(const ControlMessage& message) {
  switch (messageType(message)) {
    case MessageType::ModelBegin: {
      const ModelBegin& begin = std::get<ModelBegin>(message);
      m_receiver.begin(begin);
      emit modelProgress(0, begin.totalSize);
      return;
    }
    case MessageType::ModelChunk:
      onModelChunk(std::get<ModelChunk>(message));
      return;
    case MessageType::Keyframe:
      onKeyframe(std::get<Keyframe>(message));
      return;
    case MessageType::PeerList:
      m_peers = std::get<PeerList>(message);
      emit peersChanged();
      return;
    case MessageType::LevelList:
      m_levels = std::get<LevelList>(message);
      emit levelsChanged();
      return;
    case MessageType::LockNotice:
      sendLock(m_lock->apply(std::get<LockNotice>(message), nowMillis()));
      emit lockChanged();
      return;
    case MessageType::Heartbeat:
      return;
    case MessageType::Leave:
      m_secondTimer->stop();
      m_renewTimer->stop();
      m_channel->close();
      m_errorText = QStringLiteral("the host ended the session");
      changeState(State::Left);
      m_socket->abort();
      return;
    default:
      fail(QStringLiteral("protocol error from the host: unexpected message %1").arg(describe(messageType(message))));
      return;
  }
}

// --- sending

bool SessionClient::requestResolution(std::uint32_t wantedVertices) {
  if (!live()) return false;
  send(ResolutionRequest{wantedVertices});
  return true;
}

bool SessionClient::requestLock() {
  if (!live() || !m_lock) return false;
  const std::optional<LockMessage> message = m_lock->request(nowMillis());
  sendLock(message);
  if (message) emit lockChanged();
  return message.has_value();
}

bool SessionClient::releaseLock() {
  if (!live() || !m_lock) return false;
  const std::optional<LockMessage> message = m_lock->release(nowMillis());
  sendLock(message);
  if (message) emit lockChanged();
  return message.has_value();
}

bool SessionClient::sendConstraints(std::vector<std::vector<std::uint32_t>> groups,
                                    std::vector<std::uint32_t> anchors) {
  if (!live() || !m_lock || !m_lock->canDrag()) return false;
  const QByteArray frame =
      encodeControlMessage(Constraints{m_lock->heldEpoch(), std::move(groups), std::move(anchors)});
  if (frame.isEmpty()) return false;
  m_socket->write(frame);
  return true;
}

bool SessionClient::sendDrag(std::vector<HandleTransform> handles) {
  if (!live() || !m_lock || !m_lock->canDrag()) return false;
  const QByteArray frame = encodeControlMessage(Drag{m_lock->heldEpoch(), std::move(handles)});
  if (frame.isEmpty()) return false;
  m_socket->write(frame);
  return true;
}

void SessionClient::setImpairment(std::optional<ImpairmentSettings> settings) {
  m_options.impairment = settings;
  m_channel->setImpairment(std::move(settings));
}

void SessionClient::setDistortion(double maxPct, double meanPct, double lastPct) {
  m_hdMax = maxPct;
  m_hdMean = meanPct;
  m_hdLast = lastPct;
}

// --- timers

void SessionClient::renewTick() {
  if (live() && m_lock) sendLock(m_lock->pollRenew(nowMillis()));
}

void SessionClient::everySecond() {
  if (!live()) return;
  const Micros now = sessionNow();
  if (now - m_lastHeard > std::chrono::duration_cast<Micros>(m_options.hostTimeout)) {
    fail(QStringLiteral("host lost: not responding for %1 s").arg(m_options.hostTimeout.count() / 1000.0));
    return;
  }
  send(Heartbeat{m_heartbeatSequence++});
  const ReceiverReport r = m_channel->report(now);
  StatsReport stats;
  stats.vertexCount = levelVertexCount();
  stats.framesApplied = static_cast<std::uint32_t>(m_channel->framesApplied());
  stats.received = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.received));
  stats.lost = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.cumulativeLost));
  stats.late = r.late;
  stats.dropped = m_channel->droppedDatagrams();
  stats.lossFraction = figure(r.lossFraction);
  stats.jitterMs = figure(r.jitterMs);
  stats.payloadKbpsIn = figure(r.payloadKbps);
  stats.wireKbpsIn = figure(r.wireKbps);
  stats.framesPerSecond = figure(r.framesPerSecond);
  stats.latencyP50Ms = figure(r.latencyP50Ms);
  stats.latencyP99Ms = figure(r.latencyP99Ms);
  stats.hdMaxPct = figure(m_hdMax);
  stats.hdMeanPct = figure(m_hdMean);
  stats.hdLastPct = figure(m_hdLast);
  send(stats);
}

}  // namespace sc::session
