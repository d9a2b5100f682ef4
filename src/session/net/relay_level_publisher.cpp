#include "session/net/relay_level_publisher.h"

#include "session/net/level_library.h"
#include "session/net/relay_publisher.h"
#include "session/net/session_host.h"
#include "session/net/tls_identity.h"
#include "session/wire/relay_message.h"

#include <QtCore/QCryptographicHash>
#include <QtCore/QMetaObject>

#include <algorithm>
#include <utility>

namespace sc::session {

RelayLevelPublisher::RelayLevelPublisher(SessionHost& host, NatsConnection& nats, RelayLevelPublisherOptions options,
                                         QObject* parent)
    : QObject(parent), m_host(host), m_nats(nats), m_options(std::move(options)) {}

RelayLevelPublisher::~RelayLevelPublisher() {
  {
    const std::lock_guard lock(m_mutex);
    m_stop = true;
  }
  m_wake.notify_all();
  if (m_worker.joinable()) m_worker.join();
}

bool RelayLevelPublisher::start(QString* error) {
  auto fail = [error](const QString& why) {
    if (error) *error = why;
    return false;
  };
  if (!isValidSessionId(m_options.sessionId)) return fail(QStringLiteral("invalid session id"));
  const std::shared_ptr<const TlsIdentity> identity = m_host.identity();
  if (!identity) return fail(QStringLiteral("the host has no TLS identity yet (start it first)"));
  m_signer = std::make_unique<RelaySigner>(identity->privateKey.toDer(), m_options.sessionId);
  if (!m_signer->valid()) return fail(QStringLiteral("the host's key cannot sign relay messages"));
  QString why;
  m_stream = m_nats.createStream(relayLevelStream(m_options.sessionId), relayLevelSubjects(m_options.sessionId), &why);
  if (!m_stream) return fail(QStringLiteral("NATS level stream: ") + why);
  m_kv = m_nats.bindBucket(relayBucket(m_options.sessionId), &why);
  if (!m_kv) return fail(QStringLiteral("NATS key-value bucket: ") + why);
  std::uint32_t chunk = std::clamp<std::uint32_t>(m_options.chunkBytes, 1, kMaxRelayChunkBytes);
  if (const std::int64_t limit = m_nats.maxPayload(); limit > 0) {
    chunk = static_cast<std::uint32_t>(std::min<std::int64_t>(chunk, limit));
  }
  LevelLibrary& levels = m_host.levels();
  m_list.rowCount = m_host.model().rowCount();
  m_list.vertexCount = static_cast<std::uint32_t>(m_host.model().vertexCount());
  m_list.chunkBytes = chunk;
  m_list.total = static_cast<std::uint8_t>(levels.ladder().size() + 1);
  if (!storeList(&why)) return fail(why);
  m_worker = std::thread([this] { work(); });
  connect(&levels, &LevelLibrary::levelReady, this, &RelayLevelPublisher::onLevelReady);
  onLevelReady(levels.fullTarget());
  for (const std::uint32_t target : levels.ladder()) onLevelReady(target);
  levels.prefetchAll();
  return true;
}

void RelayLevelPublisher::onLevelReady(std::uint32_t target) {
  const LevelLibrary& levels = m_host.levels();
  const LevelLibrary::Level* level = levels.find(target);
  if (!level) return;  // not built yet: levelReady() comes later
  const auto& ladder = levels.ladder();
  const auto rung = std::find(ladder.begin(), ladder.end(), target);
  if (target != levels.fullTarget() && rung == ladder.end()) return;
  Job job;
  job.entry.index = target == levels.fullTarget() ? 0 : static_cast<std::uint8_t>(rung - ladder.begin() + 1);
  if (m_list.find(job.entry.index)) return;  // published once
  job.entry.vertexCount = level->vertexCount;
  job.entry.faceCount = level->faceCount;
  job.entry.payloadBytes = static_cast<std::uint32_t>(level->payload.size());
  job.entry.canonicalSha256 = level->sha256;
  job.payload = level->payload;  // shared, not copied
  {
    const std::lock_guard lock(m_mutex);
    for (const Job& queued : m_jobs) {
      if (queued.entry.index == job.entry.index) return;
    }
    m_jobs.push_back(std::move(job));
  }
  m_wake.notify_one();
}

void RelayLevelPublisher::work() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(m_mutex);
      m_wake.wait(lock, [this] { return m_stop || !m_jobs.empty(); });
      if (m_stop) return;
      // The smallest waiting level first: a viewer's first view arrives soonest.
      const auto smallest = std::min_element(m_jobs.begin(), m_jobs.end(), [](const Job& a, const Job& b) {
        return a.entry.payloadBytes < b.entry.payloadBytes;
      });
      job = std::move(*smallest);
      m_jobs.erase(smallest);
    }
    Done done;
    done.entry = job.entry;
    done.entry.payloadSha256 = QCryptographicHash::hash(job.payload, QCryptographicHash::Sha256);
    const std::uint32_t count = relayChunkCount(job.entry.payloadBytes, m_list.chunkBytes);
    for (std::uint32_t i = 0; i < count && done.error.isEmpty(); ++i) {
      {
        const std::lock_guard lock(m_mutex);
        if (m_stop) return;
      }
      const QByteArrayView chunk = QByteArrayView(job.payload)
                                       .sliced(static_cast<qsizetype>(i) * m_list.chunkBytes,
                                               relayChunkSize(job.entry.payloadBytes, m_list.chunkBytes, i));
      QString why;
      if (m_stream->publish(relayLevelChunkSubject(m_options.sessionId, job.entry.index, i), chunk, &why)) {
        ++done.chunks;
      } else {
        done.error = QStringLiteral("chunk %1 of %2 refused: %3").arg(i).arg(count).arg(why);
      }
    }
    QMetaObject::invokeMethod(
        this, [this, done] { finish(done); }, Qt::QueuedConnection);
  }
}

void RelayLevelPublisher::finish(const Done& done) {
  if (!done.error.isEmpty()) {
    ++m_counters.failures;
    emit levelFailed(done.entry.index, done.error);
    return;
  }
  m_counters.chunks += done.chunks;
  m_counters.bytes += done.entry.payloadBytes;
  const auto at = std::lower_bound(m_list.levels.begin(), m_list.levels.end(), done.entry.index,
                                   [](const RelayLevelEntry& e, std::uint8_t index) { return e.index < index; });
  m_list.levels.insert(at, done.entry);
  QString why;
  if (!storeList(&why)) {
    ++m_counters.failures;
    emit levelFailed(done.entry.index, why);
    return;
  }
  ++m_counters.levels;
  emit levelPublished(done.entry.index);
}

bool RelayLevelPublisher::storeList(QString* error) {
  if (m_kv->put("levels", m_signer->sign(encodeRelayLevelListBody(m_list)))) return true;
  if (error) *error = QStringLiteral("NATS: cannot store the level list");
  return false;
}

}  // namespace sc::session
