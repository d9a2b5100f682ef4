#pragma once
// The host's level payloads through the relay (issue 18 item 1; wire/relay_level_list.h has the layout): a thin
// adapter beside RelayPublisher that follows the host's LevelLibrary and publishes every built level ONCE — the
// payload a TLS joiner's transfer carries, cut into chunks on the JetStream stream SC_<sid>_LEVELS — then stores the
// signed list of the published levels under the bucket's key `levels`.
//   start(): creates (or updates) the stream, binds the session's bucket (RelayPublisher::start() created it),
//   stores the (empty) list, asks the library to build every level (prefetchAll) and queues those already built.
// The chunks are published on ONE worker std::thread (each waits for the stream's acknowledgement: about 40 round
// trips for a 10 MB level at 256 KiB per chunk), the smallest waiting level first, so the owner's thread never waits
// on a level; the list is signed and stored on the owner's thread when a level's last chunk is acknowledged (one
// round trip per level). The destructor stops the worker after the chunk in flight and joins it.

#include "session/net/nats_client.h"
#include "session/wire/relay_level_list.h"

#include <QtCore/QByteArray>
#include <QtCore/QObject>
#include <QtCore/QString>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

namespace sc::session {

class RelaySigner;
class SessionHost;

struct RelayLevelPublisherOptions {
  QString sessionId;                      ///< isValidSessionId()
  std::uint32_t chunkBytes = 256u << 10;  ///< per chunk, 1..kMaxRelayChunkBytes; capped at the server's max_payload
};

/// What the level publisher sent.
struct RelayLevelCounters {
  std::int64_t levels = 0;    ///< levels whose every chunk was acknowledged and that the list names
  std::int64_t chunks = 0;    ///< chunks acknowledged
  std::int64_t bytes = 0;     ///< payload bytes acknowledged
  std::int64_t failures = 0;  ///< levels that could not be published (a chunk or the list refused)
};

class RelayLevelPublisher final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(RelayLevelPublisher)

 public:
  /// @param host  started, outliving this publisher; @param nats  connected (RelayPublisher::connection()), outliving
  /// it.
  RelayLevelPublisher(SessionHost& host, NatsConnection& nats, RelayLevelPublisherOptions options,
                      QObject* parent = nullptr);
  ~RelayLevelPublisher() override;

  /// False with `error` when the stream or the bucket cannot be used, or the host cannot sign.
  bool start(QString* error = nullptr);
  /// The list as last stored (index ascending).
  [[nodiscard]] const RelayLevelList& list() const { return m_list; }
  [[nodiscard]] const RelayLevelCounters& counters() const { return m_counters; }
  /// True once every level of the host's ladder is listed.
  [[nodiscard]] bool complete() const { return !m_list.levels.empty() && m_list.levels.size() == m_list.total; }

 signals:
  void levelPublished(std::uint8_t index);
  void levelFailed(std::uint8_t index, const QString& reason);

 private:
  struct Job {
    RelayLevelEntry entry;  ///< payloadSha256 filled by the worker
    QByteArray payload;
  };
  struct Done {
    RelayLevelEntry entry;
    QString error;
    std::int64_t chunks = 0;
  };
  void onLevelReady(std::uint32_t target);
  void work();
  void finish(const Done& done);
  bool storeList(QString* error);

  SessionHost& m_host;
  NatsConnection& m_nats;
  RelayLevelPublisherOptions m_options;
  std::unique_ptr<RelaySigner> m_signer;
  std::unique_ptr<NatsStream> m_stream;
  std::unique_ptr<NatsKeyValue> m_kv;
  RelayLevelList m_list;
  RelayLevelCounters m_counters;

  std::mutex m_mutex;  ///< guards m_jobs and m_stop
  std::condition_variable m_wake;
  std::deque<Job> m_jobs;
  bool m_stop = false;
  std::thread m_worker;
};

}  // namespace sc::session
