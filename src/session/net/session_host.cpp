// SessionHost: construction, start/shutdown, the host's own user, and carrying out the engine's actions (sends,
// frames, transfers, level builds, closes, signals) with the one timer. Socket events are translated into engine
// events in session_host_peers.cpp.

#include "session/net/session_host.h"

#include "session/engine/session_clock.h"
#include "session/net/host_datagram_channel.h"
#include "session/net/host_peer_connection.h"
#include "session/net/level_library.h"
#include "session/net/tls_server.h"
#include "session/wire/model_transfer.h"

#include <QtCore/QPointer>
#include <QtCore/QThreadPool>
#include <QtCore/QTimer>

#include <algorithm>

namespace sc::session {

SessionHost::SessionHost(std::shared_ptr<const HostModel> model, SessionHostOptions options, QObject* parent)
    : QObject(parent),
      m_model(std::move(model)),
      m_options(std::move(options)),
      m_server(new TlsServer(this)),
      m_channel(new HostDatagramChannel(m_options.codec, this)),
      m_levels(new LevelLibrary(m_model, m_options.levelBuilder, this)),
      m_timer(new QTimer(this)),
      m_solver(new QThreadPool(this)),
      m_engine(m_model, m_options, m_levels->ladder()) {
  m_timer->setSingleShot(true);
  m_timer->setTimerType(Qt::PreciseTimer);
  m_solver->setMaxThreadCount(1);
  connect(m_server, &QTcpServer::newConnection, this, &SessionHost::acceptConnections);
  connect(m_levels, &LevelLibrary::levelReady, this, &SessionHost::onLevelReady);
  connect(m_levels, &LevelLibrary::levelFailed, this, &SessionHost::onLevelFailed);
  connect(m_timer, &QTimer::timeout, this, &SessionHost::onTimer);
}

SessionHost::~SessionHost() {
  m_solver->waitForDone();  // a running factorisation reads the engine's deformer, destroyed before the children
  for (auto& [id, connection] : m_peers) disconnect(connection, nullptr, this, nullptr);
}

bool SessionHost::start(QString* error) {
  const auto fail = [error](const QString& why) {
    if (error) *error = why;
    return false;
  };
  if (m_started) return fail(QStringLiteral("the host is already started"));
  if (!isAcceptableDisplayName(m_options.hostName) || m_options.hostName.toUtf8().size() > kMaxNameBytes) {
    return fail(QStringLiteral("host name \"%1\" is not a valid display name").arg(m_options.hostName));
  }
  if (m_model->rowCount() < 1 || m_model->rowCount() > kMaxRows || m_model->vertexCount() < 3) {
    return fail(QStringLiteral("the model needs 1..%1 basis functions and at least 3 vertices").arg(kMaxRows));
  }
  if (!resolveIdentity(error)) return false;
  m_server->setSslConfiguration(hostTlsConfiguration(m_identity->certificate, m_identity->privateKey));
  if (m_options.password) {
    const std::uint32_t iterations = std::clamp<std::uint32_t>(m_options.pbkdf2Iterations, 1, kMaxPbkdf2Iterations);
    m_secret = makeSessionSecret(*m_options.password, iterations, secureRandomBytes);
    // Only the derived key is needed from here on: the host's copy of the password goes (overwritten where this
    // object is its only holder; a caller's copy is the caller's to drop).
    m_options.password->fill(QChar(u'\0'));
    m_options.password.reset();
  }
  QString channelError;
  if (!m_channel->bind(m_options.address, m_options.udpPort, &channelError)) {
    return fail(QStringLiteral("UDP bind failed: %1").arg(channelError));
  }
  if (!m_server->listen(m_options.address, m_options.tcpPort)) {
    return fail(QStringLiteral("TCP listen failed: %1").arg(m_server->errorString()));
  }
  m_started = true;
  // The smallest level is prepared from the start, so that a progressive join's preview (issue 17 item 4) never
  // waits for a decimation, nor behind the full model's build.
  m_levels->request(m_levels->smallestTarget());
  apply(m_engine.start(sessionNow()));
  static_cast<HostEngineOptions&>(m_options) = m_engine.options();  // the limits as clamped
  emit logMessage(QStringLiteral("hosting on TCP %1, UDP %2").arg(tcpPort()).arg(udpPort()));
  emit logMessage(QStringLiteral("certificate fingerprint (SHA-256): %1").arg(formatFingerprint(fingerprint())));
  return true;
}

bool SessionHost::resolveIdentity(QString* error) {
  m_identity = m_options.identity;
  if (m_identity) {
    if (!m_identity->certificate.isNull() && !m_identity->privateKey.isNull()) return true;
    if (error) *error = QStringLiteral("the TLS identity has no certificate or no key");
    return false;
  }
  QString why;
  const QString directory = defaultTlsIdentityDirectory();
  if (std::optional<TlsIdentity> stored = loadOrCreateTlsIdentity(directory, &why)) {
    m_identity = std::make_shared<const TlsIdentity>(std::move(*stored));
    return true;
  }
  emit logMessage(QStringLiteral("cannot use the stored TLS identity (%1): using a new one for this run").arg(why));
  std::optional<TlsIdentity> fresh = generateTlsIdentity(QStringLiteral("ShapeCast host"), &why);
  if (!fresh) {
    if (error) *error = QStringLiteral("no TLS identity: %1").arg(why);
    return false;
  }
  m_identity = std::make_shared<const TlsIdentity>(std::move(*fresh));
  return true;
}

void SessionHost::shutdown() {
  if (m_engine.isShutDown()) return;
  m_server->close();
  apply(m_engine.shutdown(sessionNow()));
}

quint16 SessionHost::tcpPort() const { return m_server->serverPort(); }
quint16 SessionHost::udpPort() const { return m_channel->port(); }

// --- the host's own user

bool SessionHost::requestLock() {
  bool sent = false;
  apply(m_engine.requestLock(sessionNow(), &sent));
  return sent;
}

bool SessionHost::releaseLock() {
  bool sent = false;
  apply(m_engine.releaseLock(sessionNow(), &sent));
  return sent;
}

bool SessionHost::kick(PeerId peer, const QString& text) {
  bool kicked = false;
  apply(m_engine.kick(peer, sessionNow(), text, &kicked));
  return kicked;
}

bool SessionHost::forceReleaseLock(PeerId holder) {
  bool revoked = false;
  apply(m_engine.forceReleaseLock(sessionNow(), &revoked, holder));
  return revoked;
}

bool SessionHost::setConstraints(const spectral::ConstraintSet& constraints) {
  bool accepted = false;
  apply(m_engine.setConstraints(constraints, sessionNow(), &accepted));
  return accepted;
}

bool SessionHost::drag(std::span<const spectral::HandleTransform> poses) {
  bool accepted = false;
  apply(m_engine.drag(poses, sessionNow(), &accepted));
  return accepted;
}

bool SessionHost::endStroke() {
  bool accepted = false;
  apply(m_engine.endStroke(sessionNow(), &accepted));
  return accepted;
}

bool SessionHost::edit(EditAction action) {
  bool applied = false;
  apply(m_engine.edit(action, sessionNow(), &applied));
  return applied;
}
void SessionHost::setPresence(const Presence& presence) { apply(m_engine.setLocalPresence(presence, sessionNow())); }

// --- the engine's actions

void SessionHost::onTimer() {
  for (const auto& [id, connection] : m_peers) m_engine.onHeard(id, connection->lastHeard());
  apply(m_engine.tick(sessionNow()));
}

void SessionHost::reportSendQueues() {
  if (m_reportingQueues) return;
  m_reportingQueues = true;
  const Micros now = sessionNow();
  HostActions answers;  // collected first: carrying them out may close connections (m_peers changes)
  for (const auto& [id, c] : m_peers) {
    if (c->isClosing()) continue;
    HostActions step = m_engine.onSendQueue(id, c->sendQueue(), now);
    answers.list.insert(answers.list.end(), step.list.begin(), step.list.end());
  }
  for (const HostAction& action : answers.list) applyOne(action);
  m_reportingQueues = false;
}

qint64 SessionHost::queuedBytes(PeerId peer) const {
  const HostPeerConnection* c = connection(peer);
  return c == nullptr ? 0 : c->queuedBytes();
}

void SessionHost::apply(HostActions actions) {
  for (const HostAction& action : actions.list) applyOne(action);
  reportSendQueues();
  // The engine's wake-up as of now: an action may have led to a nested event (a close) since `actions` was made.
  const std::optional<Micros> wakeAt = m_engine.nextWakeUp();
  if (!wakeAt) {
    m_timer->stop();
    return;
  }
  const auto wait = std::chrono::ceil<Millis>(*wakeAt - sessionNow());
  m_timer->start(std::max<int>(0, static_cast<int>(wait.count())));
}

void SessionHost::applyOne(const HostAction& action) {
  if (const auto* send = std::get_if<SendToPeer>(&action)) {
    if (HostPeerConnection* c = connection(send->peer)) c->send(send->message);
  } else if (const auto* all = std::get_if<SendToAll>(&action)) {
    broadcast(all->message);
  } else if (const auto* frame = std::get_if<SendFrame>(&action)) {
    m_channel->sendFrame(frame->frame, *frame->Z, frame->stamp);
    m_frameStamp = frame->stamp;
    emit frameSent(frame->frame);
  } else if (const auto* transfer = std::get_if<StartTransfer>(&action)) {
    startTransfer(*transfer);
  } else if (const auto* request = std::get_if<RequestLevel>(&action)) {
    m_levels->request(request->target);
  } else if (std::holds_alternative<PrefetchLevels>(action)) {
    m_levels->prefetchAll();
  } else if (const auto* prepare = std::get_if<PrepareConstraints>(&action)) {
    prepareConstraints(*prepare);
  } else if (const auto* close = std::get_if<ClosePeer>(&action)) {
    closePeer(*close);
  } else if (const auto* expire = std::get_if<ExpireHandshake>(&action)) {
    if (HostPeerConnection* c = connection(expire->peer)) c->tickHandshake(toMillis(sessionNow()));
  } else if (std::holds_alternative<PeersChanged>(action)) {
    emit peersChanged();
  } else if (std::holds_alternative<LockChanged>(action)) {
    emit lockChanged();
  } else if (std::holds_alternative<EditHistoryChanged>(action)) {
    emit editHistoryChanged();
  } else if (const auto* stats = std::get_if<StatsReported>(&action)) {
    emit statsReported(stats->peer, stats->report);
  } else if (const auto* log = std::get_if<LogLine>(&action)) {
    emit logMessage(log->text);
  } else if (const auto* presence = std::get_if<PresenceReceived>(&action)) {
    emit presenceReceived(presence->presence);
  }
}

void SessionHost::broadcast(const ControlMessage& message) {
  const QByteArray frame = encodeControlMessage(message);
  if (frame.isEmpty()) return;
  for (const auto& [id, c] : m_peers) {
    if (c->isWelcomed()) c->sendEncoded(frame);
  }
}

void SessionHost::startTransfer(const StartTransfer& transfer) {
  const LevelLibrary::Level* level = m_levels->find(transfer.target);
  HostPeerConnection* c = connection(transfer.peer);
  if (level == nullptr || c == nullptr) return;
  c->startTransfer(std::make_unique<ModelSender>(transfer.transferId, level->kind, level->vertexCount, level->payload,
                                                 level->sha256));
}

void SessionHost::prepareConstraints(const PrepareConstraints& job) {
  const spectral::SpectralDeformer* deformer = &m_engine.deformer();
  const std::uint64_t ticket = job.ticket;
  const std::shared_ptr<const spectral::ConstraintSet> constraints = job.constraints;
  m_solver->start([this, deformer, ticket, constraints] {
    auto prepared = std::make_shared<std::optional<spectral::PreparedConstraints>>(deformer->prepare(*constraints));
    // Back on this object's thread; dropped by Qt if the host is gone by then.
    QMetaObject::invokeMethod(
        this,
        [this, ticket, prepared] { apply(m_engine.onConstraintsPrepared(ticket, std::move(*prepared), sessionNow())); },
        Qt::QueuedConnection);
  });
}

void SessionHost::closePeer(const ClosePeer& close) {
  HostPeerConnection* c = connection(close.peer);
  if (c == nullptr) return;
  if (close.how == ClosePeer::How::Abort) {
    c->abort();  // onClosed() follows at once
  } else {
    c->close();
  }
}

HostPeerConnection* SessionHost::connection(PeerId id) const {
  const auto it = m_peers.find(id);
  return it == m_peers.end() ? nullptr : it->second;
}

}  // namespace sc::session
