#include "session/net/relay_viewer.h"

#include "session/engine/session_clock.h"
#include "session/net/relay_publisher.h"
#include "spectral/hausdorff.h"

#include <QtCore/QRandomGenerator>
#include <QtCore/QTimer>

#include <algorithm>
#include <utility>

namespace sc::session {

RelayViewer::RelayViewer(RelayViewerOptions options, QObject* parent)
    : QObject(parent),
      m_options(std::move(options)),
      m_receiver(m_options.sessionId, m_options.pin),
      m_inbox(m_options.pendingLimit, this, [this] { drain(); }),
      m_viewerId(QRandomGenerator::system()->generate64()),
      m_display(m_options.concealment, m_options.predictor) {
  if (m_options.sharedVerification) m_receiver.shareVerification(m_options.sharedVerification);
  m_predictTimer = new QTimer(this);
  m_predictTimer->setSingleShot(true);
  m_predictTimer->setTimerType(Qt::PreciseTimer);
  connect(m_predictTimer, &QTimer::timeout, this, &RelayViewer::predict);
}

RelayViewer::~RelayViewer() {
  if (m_referenceRead.valid()) m_referenceRead.wait();  // it reads through m_kv
  m_subscription.reset();                               // no handler runs after this
  m_kv.reset();
  m_nats.reset();
}

bool RelayViewer::start(QString* error) {
  auto fail = [error](const QString& why) {
    if (error) *error = why;
    return false;
  };
  if (!isValidSessionId(m_options.sessionId)) return fail(QStringLiteral("invalid session id"));
  QString why;
  m_nats = NatsConnection::connect(m_options.nats, &why);
  if (!m_nats) return fail(QStringLiteral("NATS: ") + why);
  // Subscribe first: frames published while the keyframe is read wait in the receiver. The handler runs on a
  // cnats thread while this object lives (the destructor ends the subscription first, which waits for a running
  // handler) and touches the inbox only.
  m_subscription = m_nats->subscribe(
      relayFrameSubject(m_options.sessionId), std::max(1, m_options.pendingLimit),
      [this](QByteArrayView data) { m_inbox.push(data); }, &why);
  if (!m_subscription) return fail(QStringLiteral("NATS subscribe: ") + why);
  m_kv = m_nats->bindBucket(relayBucket(m_options.sessionId), &why);
  if (!m_kv) return fail(QStringLiteral("NATS: no session %1 (%2)").arg(m_options.sessionId, why));
  const std::optional<QByteArray> facts = m_kv->get("session");
  if (!facts) return fail(QStringLiteral("NATS: the session's facts cannot be read"));
  switch (m_receiver.onFacts(*facts)) {
    case RelayFactsStatus::None:
      break;
    case RelayFactsStatus::WrongFingerprint:
      return fail(QStringLiteral("the session's host certificate is not the pinned one"));
    case RelayFactsStatus::BadSignature:
    case RelayFactsStatus::Malformed:
      return fail(QStringLiteral("the session's facts are not authentic"));
  }
  const std::optional<QByteArray> keyframe = m_kv->get("keyframe");
  if (!keyframe || !m_receiver.onKeyframe(*keyframe, sessionNow())) m_receiver.startWithoutKeyframe(sessionNow());
  if (m_receiver.frame()) {
    showApplied();
    emit frameApplied(*m_receiver.frame());
  }
  if (m_options.referenceEvery.count() > 0) {
    m_referenceTimer = new QTimer(this);
    m_referenceTimer->setInterval(m_options.referenceEvery);
    connect(m_referenceTimer, &QTimer::timeout, this, &RelayViewer::referenceTick);
    if (m_level) m_referenceTimer->start();  // without a level nothing is read (headless viewers, the fan-out)
  }
  if (m_options.statsEvery.count() > 0) {
    auto* timer = new QTimer(this);
    connect(timer, &QTimer::timeout, this, &RelayViewer::publishStats);
    timer->start(m_options.statsEvery);
  }
  return true;
}

void RelayViewer::drain() {
  if (m_paused) return;  // the inbox keeps its newest messages (and posts nothing more) until setPaused(false)
  bool changed = false;
  for (const QByteArray& message : m_inbox.take()) {
    if (!m_receiver.onFrame(message, sessionNow())) continue;
    changed = true;
    m_display.applied(*m_receiver.frame(), m_receiver.coefficients(), sessionNow());  // each one: the probe's history
  }
  if (!changed) return;
  armPrediction();
  emit frameApplied(*m_receiver.frame());
  emit displayChanged(m_display.displayedFrame());
}

void RelayViewer::showApplied() {
  m_display.applied(*m_receiver.frame(), m_receiver.coefficients(), sessionNow());
  armPrediction();
  emit displayChanged(m_display.displayedFrame());
}

void RelayViewer::armPrediction() {
  const std::optional<Micros> due = m_display.nextDue();
  if (!due) {
    m_predictTimer->stop();
    return;
  }
  const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(*due - sessionNow());
  m_predictTimer->start(std::max(std::chrono::milliseconds{0}, wait));
}

void RelayViewer::predict() {
  if (m_display.advance(sessionNow()) != FramePredictor::Step::None) emit displayChanged(m_display.displayedFrame());
  armPrediction();
}

void RelayViewer::setLevel(spectral::SharedDisplayLevel level) {
  m_level = std::move(level);
  m_diagonal = m_level ? spectral::boundingBoxDiagonal(m_level->level.restV) : 0.0;
  if (m_referenceTimer && m_level && !m_referenceTimer->isActive()) m_referenceTimer->start();
}

void RelayViewer::referenceTick() {
  if (m_referenceRead.valid()) {
    if (m_referenceRead.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;  // still reading
    const std::optional<QByteArray> keyframe = m_referenceRead.get();
    if (keyframe) {
      if (std::optional<RelayFrame> exact = m_receiver.onReference(*keyframe))
        m_display.reference(exact->frame, exact->Z);
    }
  }
  if (m_level && m_diagonal > 0) m_display.measure(m_level->level, m_diagonal);
  if (!m_level || !m_kv) return;  // without a level nothing can be measured: no reads
  NatsKeyValue* kv = m_kv.get();
  m_referenceRead = std::async(std::launch::async, [kv] { return kv->get("keyframe"); });
}

void RelayViewer::setPaused(bool paused) {
  m_paused = paused;
  if (!paused) drain();
}

void RelayViewer::publishStats() {
  const RelayViewerStats s = stats();
  RelayStats out;
  out.viewer = m_viewerId;
  out.applied = static_cast<std::uint64_t>(s.applied);
  out.lost = static_cast<std::uint64_t>(s.lost);
  out.badSignature = static_cast<std::uint64_t>(s.badSignature);
  out.dropped = static_cast<std::uint64_t>(droppedPending());
  out.latencyP50Ms = s.latencyP50Ms;
  out.latencyP99Ms = s.latencyP99Ms;
  const RelayDisplayCounts shown = m_display.counts();
  out.concealed = shown.predicted;
  out.distortions = m_display.distortion().count;
  out.distortionMeanPct = m_display.distortion().meanPct;
  out.distortionMaxPct = m_display.distortion().maxPct;
  m_nats->publish(relayStatsSubject(m_options.sessionId, m_viewerId), encodeRelayStats(out));
}

RelayViewerStats RelayViewer::stats() const { return m_receiver.stats(sessionNow()); }

std::int64_t RelayViewer::droppedPending() const {
  return m_inbox.dropped() + (m_subscription ? m_subscription->dropped() : 0);
}

}  // namespace sc::session
