#pragma once
// A viewer's level from the relay's stream (issue 18 item 1; wire/relay_level_list.h has the layout; the host side is
// relay_level_publisher.h). fetch(index) runs on ONE worker std::thread at a time (the latest request wins):
//   1. read the `levels` key and verify it with the host's certificate (the facts the viewer pinned), check it
//      against the session (m, n; every level's sizes within checkLevelList()'s bounds); a level not listed yet is
//      waited for (re-read every 200 ms) up to `listWait`;
//   2. refuse a level whose signed size exceeds `maxLevelBytes` BEFORE anything is allocated for it;
//   3. read its chunks in order, each at most its exact size (a missing, oversized or short chunk is refused with the
//      chunk's number), then the payload's SHA-256 against the signed one (a forged chunk is refused there);
//   4. decode it as a TLS joiner does (engine/client_level_decode.h: decompression bounded, the decoded payload's
//      SHA-256, the session's shape).
// The result comes back on the owner's thread as levelReady() or levelRefused() with the reason. The destructor joins
// the worker (a fetch in flight finishes its current round trip first: ≤ the connection's timeout).

#include "session/net/nats_client.h"
#include "session/wire/relay_level_list.h"
#include "session/wire/relay_message.h"
#include "spectral/display_level.h"

#include <QtCore/QByteArray>
#include <QtCore/QObject>
#include <QtCore/QString>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>

namespace sc::session {

struct RelayLevelFetcherOptions {
  QString sessionId;
  RelayFacts facts;  ///< accepted (pinned) facts: m, n and the certificate whose key signs the list
  std::uint64_t maxLevelBytes = 256ull << 20;  ///< the largest published payload fetched
  std::chrono::milliseconds listWait{10000};   ///< how long a level may take to be listed
};

/// One fetch's outcome and figures.
struct RelayLevelFetch {
  std::uint8_t index = 0;
  RelayLevelEntry entry;               ///< as listed (when it was)
  spectral::SharedDisplayLevel level;  ///< null when refused
  QString error;                       ///< set exactly when `level` is null
  std::uint32_t chunks = 0;            ///< chunks read
  double fetchMs = 0;                  ///< list and chunks
  double decodeMs = 0;                 ///< decompression, checks and decode
};

class RelayLevelFetcher final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(RelayLevelFetcher)

 public:
  /// @param nats  connected with the viewer credential, outliving this fetcher.
  RelayLevelFetcher(NatsConnection& nats, RelayLevelFetcherOptions options, QObject* parent = nullptr);
  ~RelayLevelFetcher() override;

  /// Binds the bucket and the stream; false with `error` when they are not readable.
  bool start(QString* error = nullptr);
  /// Fetches level `index` (0 = full model) in the background; a request made while one runs replaces any waiting one.
  void fetch(std::uint8_t index);
  /// The verified, checked list now (a round trip on the calling thread); nullopt with `error` when refused.
  std::optional<RelayLevelList> readList(QString* error = nullptr);
  /// The last outcome (levelReady/levelRefused have been emitted for it).
  [[nodiscard]] const RelayLevelFetch& last() const { return m_last; }
  [[nodiscard]] bool busy() const { return m_busy; }

 signals:
  void levelReady(std::uint8_t index, const spectral::SharedDisplayLevel& level);
  void levelRefused(std::uint8_t index, const QString& reason);

 private:
  void startWorker(std::uint8_t index);
  void finish(RelayLevelFetch result);
  /// The worker's job. Never throws.
  RelayLevelFetch run(std::uint8_t index);
  std::optional<RelayLevelList> readListWith(const RelayVerifier& verifier, QString* error);

  NatsConnection& m_nats;
  RelayLevelFetcherOptions m_options;
  std::unique_ptr<NatsKeyValue> m_kv;
  std::unique_ptr<NatsStream> m_stream;
  std::thread m_worker;
  std::atomic<bool> m_stop{false};
  bool m_busy = false;
  std::optional<std::uint8_t> m_waiting;
  RelayLevelFetch m_last;
};

}  // namespace sc::session
