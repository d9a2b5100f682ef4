#include "session/net/relay_publisher.h"

#include "session/engine/session_clock.h"
#include "session/net/session_host.h"

#include <QtCore/QTimer>

#include <utility>

namespace sc::session {
namespace {
constexpr int kTrailingKeyframeMs = 200;
}  // namespace

std::string relayFrameSubject(const QString& sessionId) { return "sc." + sessionId.toStdString() + ".z"; }
std::string relayBucket(const QString& sessionId) { return "sc_" + sessionId.toStdString(); }
std::string relayStatsSubject(const QString& sessionId, std::uint64_t viewer) {
  return "sc." + sessionId.toStdString() + ".stats." +
         QString::number(viewer, 16).rightJustified(16, u'0').toStdString();
}

namespace {
constexpr int kStatsInbox = 1024;
}  // namespace

RelayPublisher::RelayPublisher(SessionHost& host, RelayPublisherOptions options, QObject* parent)
    : QObject(parent),
      m_host(host),
      m_options(std::move(options)),
      m_bucket(relayBucket(m_options.sessionId)),
      m_statsInbox(kStatsInbox, this, [this] { drainStats(); }) {
  m_keyframeTimer = new QTimer(this);
  m_keyframeTimer->setSingleShot(true);
  m_keyframeTimer->setInterval(kTrailingKeyframeMs);
  connect(m_keyframeTimer, &QTimer::timeout, this, &RelayPublisher::storeKeyframe);
}

RelayPublisher::~RelayPublisher() {
  m_statsSubscription.reset();  // no handler runs after this
  m_kv.reset();                 // before the connection it uses
  m_nats.reset();
}

std::string RelayPublisher::frameSubject() const { return relayFrameSubject(m_options.sessionId); }

RelayBrokerLink RelayPublisher::connectToBroker(const RelayPublisherOptions& options) {
  RelayBrokerLink link;
  link.sessionId = options.sessionId;
  if (!isValidSessionId(options.sessionId)) {
    link.error = QStringLiteral("invalid session id (1..32 of A-Z a-z 0-9 _ -)");
    return link;
  }
  QString why;
  link.nats = NatsConnection::connect(options.nats, &why);
  if (!link.nats) {
    link.error = QStringLiteral("NATS: ") + why;
    return link;
  }
  const std::string bucket = relayBucket(options.sessionId);
  link.kv = link.nats->createBucket(bucket, &why);
  if (!link.kv) link.error = QStringLiteral("NATS key-value bucket %1: %2").arg(QString::fromStdString(bucket), why);
  return link;
}

bool RelayPublisher::makeSigner(QString* error) {
  auto fail = [error](const QString& why) {
    if (error) *error = why;
    return false;
  };
  if (!isValidSessionId(m_options.sessionId))
    return fail(QStringLiteral("invalid session id (1..32 of A-Z a-z 0-9 _ -)"));
  const std::shared_ptr<const TlsIdentity> identity = m_host.identity();
  if (!identity) return fail(QStringLiteral("the host has no TLS identity yet (start it first)"));
  m_signer = std::make_unique<RelaySigner>(identity->privateKey.toDer(), m_options.sessionId);
  if (!m_signer->valid()) return fail(QStringLiteral("the host's key cannot sign relay messages"));
  return true;
}

bool RelayPublisher::start(QString* error) {
  // What can fail here fails before the broker is asked for anything (no connection, no bucket left behind).
  return makeSigner(error) && start(connectToBroker(m_options), error);
}

bool RelayPublisher::start(RelayBrokerLink link, QString* error) {
  auto fail = [error](const QString& why) {
    if (error) *error = why;
    return false;
  };
  if (!makeSigner(error)) return false;
  if (link.sessionId != m_options.sessionId) return fail(QStringLiteral("the broker link is another session's"));
  if (!link.nats || !link.kv) return fail(link.error);
  const std::shared_ptr<const TlsIdentity> identity = m_host.identity();
  m_nats = std::move(link.nats);
  m_kv = std::move(link.kv);
  QString why;
  RelayFacts facts;
  facts.rowCount = m_host.model().rowCount();
  facts.vertexCount = static_cast<std::uint32_t>(m_host.model().vertexCount());
  facts.certificateDer = identity->certificate.toDer();
  if (!m_kv->put("session", m_signer->sign(encodeRelayFactsBody(facts)))) {
    return fail(QStringLiteral("NATS: cannot store the session facts"));
  }
  storeKeyframe();
  m_statsSubscription = m_nats->subscribe(
      "sc." + m_options.sessionId.toStdString() + ".stats.>", kStatsInbox,
      [this](QByteArrayView data) { m_statsInbox.push(data); }, &why);
  if (!m_statsSubscription) return fail(QStringLiteral("NATS subscribe: ") + why);
  connect(&m_host, &SessionHost::frameSent, this, &RelayPublisher::onFrame);
  return true;
}

QByteArray RelayPublisher::signedFrame() const {
  RelayFrame frame;
  frame.frame = m_host.currentFrame();
  frame.stampMicros = static_cast<std::uint64_t>(m_host.currentFrameStamp().count());
  frame.Z = m_host.coefficients();
  if (frame.Z.rows() == 0) frame.Z = Eigen::MatrixXd::Zero(m_host.model().rowCount(), 3);
  return m_signer->sign(encodeRelayFrameBody(frame));
}

void RelayPublisher::onFrame(std::uint32_t /*frame*/) {
  const QByteArray message = signedFrame();
  const bool ok = m_nats->publish(frameSubject(), message);
  ++(ok ? m_counters.frames : m_counters.failures);
  if (ok) m_counters.bytes += message.size();
  if (++m_sinceKeyframe >= m_options.keyframeEvery) storeKeyframe();
  m_keyframeTimer->start();
}

void RelayPublisher::drainStats() {
  for (const QByteArray& message : m_statsInbox.take()) m_audience.onStats(message, sessionNow());
}

RelayAudienceSummary RelayPublisher::audience() const { return m_audience.summary(sessionNow()); }

void RelayPublisher::storeKeyframe() {
  const std::uint32_t frame = m_host.currentFrame();
  if (m_stored && frame == m_storedFrame) return;
  const QByteArray message = signedFrame();
  const bool ok = m_nats->publish(natsKeySubject(m_bucket, "keyframe"), message);
  if (!ok) {
    ++m_counters.failures;
    return;
  }
  ++m_counters.keyframes;
  m_counters.bytes += message.size();
  m_stored = true;
  m_storedFrame = frame;
  m_sinceKeyframe = 0;
}

}  // namespace sc::session
