#include "session/net/relay_level_fetcher.h"

#include "session/engine/client_level_decode.h"
#include "session/net/relay_publisher.h"
#include "session/wire/control_messages.h"

#include <QtCore/QCryptographicHash>
#include <QtCore/QElapsedTimer>
#include <QtCore/QMetaObject>

#include <exception>
#include <utility>

namespace sc::session {
namespace {
constexpr int kListPollMs = 200;

double elapsedMs(const QElapsedTimer& clock) { return static_cast<double>(clock.nsecsElapsed()) / 1e6; }
}  // namespace

RelayLevelFetcher::RelayLevelFetcher(NatsConnection& nats, RelayLevelFetcherOptions options, QObject* parent)
    : QObject(parent), m_nats(nats), m_options(std::move(options)) {}

RelayLevelFetcher::~RelayLevelFetcher() {
  m_stop = true;
  if (m_worker.joinable()) m_worker.join();
}

bool RelayLevelFetcher::start(QString* error) {
  QString why;
  m_kv = m_nats.bindBucket(relayBucket(m_options.sessionId), &why);
  if (!m_kv) {
    if (error) *error = QStringLiteral("NATS: no session %1 (%2)").arg(m_options.sessionId, why);
    return false;
  }
  m_stream = m_nats.bindStream(relayLevelStream(m_options.sessionId), &why);
  if (!m_stream) {
    if (error) *error = QStringLiteral("NATS level stream: ") + why;
    return false;
  }
  return true;
}

void RelayLevelFetcher::fetch(std::uint8_t index) {
  if (m_busy) {
    m_waiting = index;
    return;
  }
  startWorker(index);
}

void RelayLevelFetcher::startWorker(std::uint8_t index) {
  if (m_worker.joinable()) m_worker.join();  // finished: finish() runs after the worker posted its result
  m_busy = true;
  m_worker = std::thread([this, index] {
    RelayLevelFetch result = run(index);
    QMetaObject::invokeMethod(
        this, [this, result = std::move(result)]() mutable { finish(std::move(result)); }, Qt::QueuedConnection);
  });
}

void RelayLevelFetcher::finish(RelayLevelFetch result) {
  m_busy = false;
  m_last = std::move(result);
  if (m_last.level) {
    emit levelReady(m_last.index, m_last.level);
  } else {
    emit levelRefused(m_last.index, m_last.error);
  }
  if (m_waiting) {
    const std::uint8_t next = *m_waiting;
    m_waiting.reset();
    startWorker(next);
  }
}

std::optional<RelayLevelList> RelayLevelFetcher::readList(QString* error) {
  const RelayVerifier verifier(m_options.facts.certificateDer, m_options.sessionId);
  return readListWith(verifier, error);
}

std::optional<RelayLevelList> RelayLevelFetcher::readListWith(const RelayVerifier& verifier, QString* error) {
  auto fail = [error](const QString& why) -> std::optional<RelayLevelList> {
    if (error) *error = why;
    return std::nullopt;
  };
  const std::optional<QByteArray> message = m_kv->get("levels");
  if (!message) return fail(QStringLiteral("the session publishes no level list"));
  RelayError why = RelayError::None;
  const std::optional<QByteArrayView> body = verifier.verify(*message, &why);
  if (!body) return fail(QStringLiteral("the level list is not signed by the session's host"));
  std::optional<RelayLevelList> list = decodeRelayLevelListBody(*body);
  if (!list) return fail(QStringLiteral("the level list is malformed"));
  if (list->rowCount != m_options.facts.rowCount || list->vertexCount != m_options.facts.vertexCount) {
    return fail(QStringLiteral("the level list is for another shape (m = %1, n = %2)")
                    .arg(list->rowCount)
                    .arg(list->vertexCount));
  }
  LevelList asListed;
  asListed.total = list->total;
  for (const RelayLevelEntry& entry : list->levels) {
    asListed.levels.push_back({entry.index, entry.vertexCount, entry.faceCount, entry.payloadBytes});
  }
  const QString bad = checkLevelList(asListed, static_cast<std::uint16_t>(list->rowCount), list->vertexCount);
  if (!bad.isEmpty()) return fail(QStringLiteral("the level list is refused: ") + bad);
  return list;
}

RelayLevelFetch RelayLevelFetcher::run(std::uint8_t index) {
  RelayLevelFetch out;
  out.index = index;
  QElapsedTimer clock;
  clock.start();
  try {
    const RelayVerifier verifier(m_options.facts.certificateDer, m_options.sessionId);
    std::optional<RelayLevelList> list;
    for (;;) {
      QString why;
      list = readListWith(verifier, &why);
      if (!list && !why.startsWith(QStringLiteral("the session publishes no level list"))) {
        out.error = why;
        return out;
      }
      if (list && list->find(index)) break;
      if (m_stop || clock.elapsed() >= m_options.listWait.count() || (list && index >= list->total)) {
        out.error = list ? QStringLiteral("level %1 is not published (%2 of %3 levels listed)")
                               .arg(index)
                               .arg(list->levels.size())
                               .arg(list->total)
                         : why;
        return out;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(kListPollMs));
    }
    out.entry = *list->find(index);
    const RelayLevelEntry& entry = out.entry;
    if (entry.payloadBytes > m_options.maxLevelBytes) {
      out.error = QStringLiteral("level %1 is %2 bytes, above this viewer's limit of %3")
                      .arg(index)
                      .arg(entry.payloadBytes)
                      .arg(m_options.maxLevelBytes);
      return out;
    }
    const std::uint32_t count = relayChunkCount(entry.payloadBytes, list->chunkBytes);
    QByteArray payload;
    payload.reserve(entry.payloadBytes);  // bounded: the signed size, checked above
    for (std::uint32_t i = 0; i < count; ++i) {
      if (m_stop) {
        out.error = QStringLiteral("stopped");
        return out;
      }
      const std::uint32_t expected = relayChunkSize(entry.payloadBytes, list->chunkBytes, i);
      NatsStream::Miss miss = NatsStream::Miss::None;
      QString why;
      const std::optional<QByteArray> chunk =
          m_stream->lastMessage(relayLevelChunkSubject(m_options.sessionId, index, i), expected, &miss, &why);
      if (!chunk) {
        switch (miss) {
          case NatsStream::Miss::Absent:
            out.error =
                QStringLiteral("chunk %1 of %2 of level %3 is missing from the stream").arg(i).arg(count).arg(index);
            break;
          case NatsStream::Miss::TooLarge:
            out.error =
                QStringLiteral("chunk %1 of %2 of level %3 is oversized: %4").arg(i).arg(count).arg(index).arg(why);
            break;
          default:
            out.error =
                QStringLiteral("chunk %1 of %2 of level %3 cannot be read: %4").arg(i).arg(count).arg(index).arg(why);
        }
        return out;
      }
      if (static_cast<std::uint32_t>(chunk->size()) != expected) {
        out.error = QStringLiteral("chunk %1 of %2 of level %3 has %4 bytes, %5 expected")
                        .arg(i)
                        .arg(count)
                        .arg(index)
                        .arg(chunk->size())
                        .arg(expected);
        return out;
      }
      payload.append(*chunk);
      ++out.chunks;
    }
    if (QCryptographicHash::hash(payload, QCryptographicHash::Sha256) != entry.payloadSha256) {
      out.error = QStringLiteral("level %1's chunks do not match the signed SHA-256 (forged or corrupted)").arg(index);
      return out;
    }
    out.fetchMs = elapsedMs(clock);
    clock.restart();
    LevelJob job;
    job.payload = std::move(payload);
    job.sha256 = entry.canonicalSha256;
    job.rowCount = static_cast<std::uint16_t>(list->rowCount);
    job.vertexCount = list->vertexCount;
    DecodedLevel decoded = decodeLevel(std::move(job));
    out.decodeMs = elapsedMs(clock);
    if (!decoded.level) {
      out.error = decoded.error;
      return out;
    }
    if (decoded.level->vertexCount() != entry.vertexCount) {
      out.error = QStringLiteral("level %1 has %2 vertices, the list says %3")
                      .arg(index)
                      .arg(decoded.level->vertexCount())
                      .arg(entry.vertexCount);
      return out;
    }
    out.level = std::move(decoded.level);
  } catch (const std::exception& e) {  // std::bad_alloc: never let it escape the worker
    out.level.reset();
    out.error = QStringLiteral("fetching level %1 failed: %2").arg(index).arg(QString::fromLocal8Bit(e.what()));
  }
  return out;
}

}  // namespace sc::session
