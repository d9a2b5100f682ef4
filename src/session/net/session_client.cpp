// SessionClient: the sockets (TLS control connection and its certificate check), the user's commands handed to the
// engine, and the one timer. The engine's actions are executed in session_client_actions.cpp; the decode worker
// and the displayed frame in session_client_level.cpp.

#include "session/net/session_client.h"

#include "session/engine/session_clock.h"
#include "session/net/tls_identity.h"
#include "session/net/tls_known_hosts.h"
#include "session/net/tls_server.h"
#include "session/net/tls_stream.h"
#include "session/wire/password_auth.h"

#include <QtCore/QTimer>

#include <algorithm>

namespace sc::session {
namespace {

/// The TLS stream's buffer and its socket's under a link rate: small (at most 32 + 3 · 16 KiB held, tls_stream.h),
/// so that TCP's flow control backs up to the host.
constexpr qint64 kLinkReadBuffer = 32 * 1024;
constexpr qint64 kLinkSocketBuffer = 16 * 1024;
/// Under a link rate, the kernel's receive buffer of the TLS socket: 20 ms at the rate, at least 64 KiB. On loopback
/// the kernel would otherwise grow both ends' buffers to megabytes; the host's socket then reports no progress
/// for seconds at a low rate (Linux wakes a writer only once half its send buffer is free) and the host drops the
/// client as stalled (HostEngineOptions::sendStallTimeout). A real slow path keeps those buffers small.
qint64 linkKernelBuffer(double bitsPerSecond) {
  return std::max<qint64>(64 * 1024, static_cast<qint64>(bitsPerSecond / 8.0 * 0.02));
}
/// Without a rate, what the TLS stream may read ahead of the engine: this much while no transfer is accepted (control
/// messages; a hostile host's oversized announcement is refused before more is read), plus the accepted transfer's
/// size while one arrives, up to kMaxReadAhead (about 5 s of a 100 Mbit/s link: a GUI thread that stands still that
/// long keeps the host's queue draining).
constexpr qint64 kControlReadAhead = 1024 * 1024;
constexpr qint64 kMaxReadAhead = 64 * 1024 * 1024;
/// Under a link rate, a waiting stream is read again once this many bytes (or all pending, if fewer) are allowed.
constexpr std::size_t kLinkReadChunk = 4096;

ClientEngineConfig engineConfig(const SessionClientOptions& options) {
  return ClientEngineConfig{options.name,
                            options.password,
                            options.level,
                            options.levelFraction,
                            std::chrono::duration_cast<Millis>(options.hostTimeout),
                            options.minPbkdf2Iterations,
                            options.keepLevelPayload,
                            options.progressive};
}

}  // namespace

SessionClient::SessionClient(SessionClientOptions options, QObject* parent)
    : QObject(parent), m_options(std::move(options)), m_engine(engineConfig(m_options)) {
  m_options.password.reset();  // the engine holds it (and drops it once its proof is made)
  m_stream = new TlsStream(clientTlsConfiguration(), this);
  m_linkTimer = new QTimer(this);
  m_linkTimer->setSingleShot(true);
  m_linkTimer->setTimerType(Qt::PreciseTimer);
  makeLink();
  m_channel =
      new ClientDatagramChannel(ClientDatagramOptions{m_options.concealment, m_options.impairment, {}, m_link}, this);
  m_timer = new QTimer(this);
  m_timer->setSingleShot(true);
  m_timer->setTimerType(Qt::PreciseTimer);
  connect(m_stream, &TlsStream::encrypted, this, &SessionClient::onEncrypted);
  connect(m_stream, &TlsStream::readyRead, this, &SessionClient::readAvailable);
  connect(m_stream, &TlsStream::disconnected, this, [this] {
    readStream(true);  // what the host sent before closing (a Leave) is not held back by the link rate
    apply(m_engine.onClosed());
  });
  connect(m_linkTimer, &QTimer::timeout, this, &SessionClient::readAvailable);
  connect(m_stream, &TlsStream::errorOccurred, this, [this](QAbstractSocket::SocketError error, const QString& text) {
    if (error == QAbstractSocket::RemoteHostClosedError) return;  // disconnected() reports it
    apply(m_engine.onTransportError(text));
  });
  connect(m_channel, &ClientDatagramChannel::frameUpdated, this, [this] {
    m_engine.onFrameChanged(sessionNow());
    armTimer();  // at once, after the datagrams already pending: one update serves them all
  });
  connect(m_timer, &QTimer::timeout, this, &SessionClient::wake);
}

SessionClient::~SessionClient() {
  // A decode in flight only posts its result to this object (a queued call, discarded with the object's pending
  // events by ~QObject): wait for it here, before any member it could be racing with is gone.
  if (m_decoder.joinable()) m_decoder.join();
  if (m_keyDeriver.joinable()) m_keyDeriver.join();
  disconnect(m_stream, nullptr, this, nullptr);
}

void SessionClient::start() { apply(m_engine.start()); }

void SessionClient::onEncrypted() {
  const QByteArray presented = certificateFingerprint(m_stream->peerCertificate());
  m_hostFingerprint = presented;  // also when refused below: the UI shows what was seen
  KnownHosts known(m_options.knownHostsFile);
  const bool tofu = m_options.trustOnFirstUse;
  const FingerprintCheck check = checkFingerprint(
      presented, m_options.fingerprint, tofu ? known.lookup(m_options.host, m_options.port) : std::nullopt, tofu);
  if (!check.accepted()) {
    apply(m_engine.fail(check.reason));
    return;
  }
  using V = FingerprintCheck::Verdict;
  if (tofu && (check.verdict == V::FirstUse || check.verdict == V::Pinned)) {
    known.remember(m_options.host, m_options.port, presented);
  }
  apply(m_engine.onSecured(presented, sessionNow()));
}

void SessionClient::execute(client_action::DerivePasswordKey& derive) {
  if (m_keyDeriver.joinable()) m_keyDeriver.join();  // one Challenge per session: a previous one has ended
  // PBKDF2 (0.35 s at the default 600,000 iterations here) runs off this thread: a GUI stays responsive meanwhile.
  m_keyDeriver = std::thread([this, request = std::move(derive.request)]() mutable {
    QByteArray key = derivePasswordKey(request.password, request.salt, request.iterations);
    // The session's copy, overwritten before it is dropped (in place unless the caller still shares it: then the
    // caller's own wipe, e.g. forgetPassword(), overwrites the original).
    request.password.fill(QChar(u'\0'));
    request.password.clear();
    // Only a queued call touches `this`; the destructor joins this thread, so the object is alive here.
    QMetaObject::invokeMethod(
        this, [this, key = std::move(key)]() mutable { finishPasswordKey(key); }, Qt::QueuedConnection);
  });
}

void SessionClient::finishPasswordKey(QByteArray& key) {
  if (m_keyDeriver.joinable()) m_keyDeriver.join();  // it has posted this call: it is ending
  apply(m_engine.onPasswordKey(key));
  key.fill('\0');  // the key answers this host's challenges as the password would: its only copy is overwritten
}

void SessionClient::readAvailable() { readStream(false); }

void SessionClient::readStream(bool unthrottled) {
  QByteArray bytes;
  if (!m_link || unthrottled) {
    bytes = m_stream->readAll();
    if (m_link) m_link->consume(static_cast<std::size_t>(bytes.size()), sessionNow());
  } else {
    // A read short of the allowance means nothing more is buffered yet: readyRead follows when it is (a read lets
    // the stream take more from the host). Reading the whole allowance means more may wait: read again when
    // kLinkReadChunk is allowed.
    const Micros now = sessionNow();
    const auto allowed = static_cast<qint64>(m_link->available(now));
    if (allowed > 0) bytes = m_stream->read(allowed);
    m_link->consume(static_cast<std::size_t>(bytes.size()), now);
    if (bytes.size() == allowed) {
      const Micros at = m_link->availableAt(kLinkReadChunk, now);
      m_linkTimer->start(static_cast<int>(std::min<Micros::rep>(((at - now).count() + 999) / 1000, 1'000'000)));
    }
  }
  if (bytes.isEmpty() || !m_engine.acceptsMessages()) return;  // after a failure or Leave nothing is kept
  m_streamBytesRead += static_cast<std::uint64_t>(bytes.size());
  m_engine.onHeard(sessionNow());
  m_reader.append(bytes);
  while (m_engine.acceptsMessages()) {
    std::optional<ControlDecodeResult> result = m_reader.next();
    if (!result) break;
    apply(m_engine.onMessage(*result, sessionNow()));
  }
}

// --- the user's commands

void SessionClient::leave() { apply(m_engine.leave()); }

bool SessionClient::requestResolution(std::uint32_t wantedVertices) {
  return applyCommand(m_engine.requestResolution(wantedVertices));
}

bool SessionClient::requestLock() { return applyCommand(m_engine.requestLock(sessionNow())); }

bool SessionClient::releaseLock() { return applyCommand(m_engine.releaseLock(sessionNow())); }

bool SessionClient::sendConstraints(std::vector<std::vector<std::uint32_t>> groups,
                                    std::vector<std::uint32_t> anchors) {
  return applyCommand(m_engine.sendConstraints(std::move(groups), std::move(anchors)));
}

bool SessionClient::endStroke() { return applyCommand(m_engine.endStroke()); }

bool SessionClient::requestEdit(EditAction action) { return applyCommand(m_engine.requestEdit(action)); }

bool SessionClient::sendDrag(std::vector<HandleTransform> handles) {
  return applyCommand(m_engine.sendDrag(std::move(handles)));
}

bool SessionClient::sendPresence(const Presence& presence) { return applyCommand(m_engine.sendPresence(presence)); }

bool SessionClient::applyCommand(ClientActions actions) {
  const bool accepted = !actions.empty();
  apply(std::move(actions));
  return accepted;
}

void SessionClient::setImpairment(std::optional<ImpairmentSettings> settings) {
  m_options.impairment = settings;
  makeLink();
  m_channel->setImpairment(std::move(settings), m_link);
  // Bytes the old link held back are read under the new one (or at once without a rate).
  if (m_stream->bytesAvailable() > 0) QTimer::singleShot(0, this, &SessionClient::readAvailable);
}

void SessionClient::makeLink() {
  const bool rated = m_options.impairment && m_options.impairment->rate.bitsPerSecond > 0.0;
  m_link = rated ? std::make_shared<LinkRate>(m_options.impairment->rate) : nullptr;
  m_readAhead = 0;
  if (rated) {
    m_stream->setBufferSizes(kLinkReadBuffer, kLinkSocketBuffer);
  } else {
    grantReadAhead(0);
  }
  m_stream->setReceiveBufferSize(rated ? linkKernelBuffer(m_link->bitsPerSecond()) : 0);
  if (!rated) m_linkTimer->stop();
}

void SessionClient::grantReadAhead(std::uint64_t transferBytes) {
  if (m_link) return;  // a rated link keeps its small buffers
  const qint64 wanted = std::min<qint64>(
      kControlReadAhead + static_cast<qint64>(std::min<std::uint64_t>(transferBytes, kMaxReadAhead)), kMaxReadAhead);
  if (wanted == m_readAhead) return;
  m_readAhead = wanted;
  m_stream->setBufferSizes(wanted, TlsStream::kDefaultSocketBuffer);
}

void SessionClient::setDistortion(double maxPct, double meanPct, double lastPct) {
  m_engine.setDistortion(maxPct, meanPct, lastPct);
}

// --- the one timer

void SessionClient::armTimer() {
  const std::optional<Micros> due = m_engine.nextWakeUp();
  if (!due) {
    m_timer->stop();
    m_armedFor.reset();
    return;
  }
  if (m_timer->isActive() && m_armedFor == due) return;  // already armed for it (e.g. a burst of frame changes)
  // Rounded up to whole milliseconds (QTimer's unit): never early, at most 1 ms late; 0 = after pending events.
  const Micros wait = std::max(Micros{0}, *due - sessionNow());
  m_timer->start(static_cast<int>(std::min<Micros::rep>((wait.count() + 999) / 1000, 1'000'000)));
  m_armedFor = due;
}

void SessionClient::wake() {
  m_armedFor.reset();
  apply(m_engine.tick(sessionNow(), [this](Micros now) { return sampleReceiver(now); }));
}

ReceiverSample SessionClient::sampleReceiver(Micros now) {
  return ReceiverSample{m_channel->report(now), m_channel->framesApplied(), m_channel->droppedDatagrams()};
}

StatsReport SessionClient::peekStats() const {
  return m_engine.statsReport(
      ReceiverSample{m_channel->peek(sessionNow()), m_channel->framesApplied(), m_channel->droppedDatagrams()});
}

}  // namespace sc::session
