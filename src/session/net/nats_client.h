#pragma once
// A small RAII wrapper over the NATS C client (cnats, <nats/nats.h>; issue 18): one connection with automatic
// reconnection, publish, subscriptions with a pending limit, and a JetStream key-value bucket. Every cnats object
// is destroyed by its owner here (natsConnection_Destroy, natsSubscription_Destroy, natsMsg_Destroy, kvStore_Destroy,
// jsCtx_Destroy); call natsShutdown() once at process end, after every wrapper is gone (nats_Close: releases the
// library's threads and memory, for LeakSanitizer).
//
// Threads: a subscription's handler and the connection's event counters run on cnats threads. The handler must not
// touch engine or Qt object state: copy the bytes into a mutex-protected queue or post them with
// QMetaObject::invokeMethod(…, Qt::QueuedConnection) (net/relay_viewer.cpp does the latter).

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace sc::session {

struct NatsConnectOptions {
  QString url;  ///< nats://host:port or tls://host:port (several: comma-separated)
  QString user;
  QString password;
  QString name;                                  ///< shown in the server's monitoring
  std::chrono::milliseconds timeout{2000};       ///< connect and request timeout
  std::chrono::milliseconds reconnectWait{100};  ///< between reconnection attempts (forever)
  bool retryOnFailedConnect = false;             ///< connect() succeeds and keeps trying when the server is down
  /// TLS to the broker: a PEM file of the CA certificate(s) to trust instead of the system's. TLS is used when a URL
  /// is tls:// or the server requires it; the server's certificate must then chain to a trusted CA and name the
  /// URL's host (a DNS name, or an IP address in its IP entries: cnats checks both).
  QString caFile;
};

/// Whether one of the comma-separated URLs in `urls` starts with tls:// (case-insensitive).
bool natsUrlWantsTls(const QString& urls);

class NatsSubscription;
class NatsKeyValue;
class NatsStream;

/// What one connection moved since it was created, as cnats counts it (natsConnection_GetStats): payload bytes and
/// messages, protocol overhead not included.
struct NatsTraffic {
  std::uint64_t inMessages = 0, inBytes = 0, outMessages = 0, outBytes = 0, reconnects = 0;
};

/// One connection. Not copyable; destroying it closes the connection (its subscriptions must be gone first).
class NatsConnection {
 public:
  /// Connects; nullptr with `error` set (cnats' text) on failure. Reconnects forever after a disconnection.
  static std::unique_ptr<NatsConnection> connect(const NatsConnectOptions& options, QString* error = nullptr);
  ~NatsConnection();
  NatsConnection(const NatsConnection&) = delete;
  NatsConnection& operator=(const NatsConnection&) = delete;

  /// Publishes `data` on `subject` (buffered by cnats; also while reconnecting, up to its reconnect buffer). False
  /// when cnats refused it. Cost: one copy into the connection's buffer.
  bool publish(const std::string& subject, QByteArrayView data);
  /// Waits until the server has processed everything published so far; false on timeout or disconnection.
  bool flush(std::chrono::milliseconds timeout);
  /// The server's last asynchronous error on this connection (e.g. "Permissions Violation for Publish to …").
  [[nodiscard]] QString lastError() const;
  /// True while connected (not reconnecting or closed).
  [[nodiscard]] bool connected() const;
  /// The connection's counters (natsConnection_GetStats); zeros when cnats cannot read them.
  [[nodiscard]] NatsTraffic traffic() const;
  /// Times the connection came back after a disconnection.
  [[nodiscard]] int reconnections() const { return m_events->reconnected.load(); }

  using Handler = std::function<void(QByteArrayView data)>;
  /// Subscribes to `subject`; `handler` runs on a cnats thread for every message, in order. At most
  /// `pendingMessages` wait for the handler: newer ones are dropped by cnats (NatsSubscription::dropped()).
  std::unique_ptr<NatsSubscription> subscribe(const std::string& subject, int pendingMessages, Handler handler,
                                              QString* error = nullptr);
  /// Creates (host) or updates the key-value bucket `bucket` with history 1; nullptr with `error` on failure.
  std::unique_ptr<NatsKeyValue> createBucket(const std::string& bucket, QString* error = nullptr);
  /// Binds to an existing bucket (viewer); nullptr with `error` when it does not exist or is not readable.
  std::unique_ptr<NatsKeyValue> bindBucket(const std::string& bucket, QString* error = nullptr);
  /// Creates (or updates) the JetStream stream `name` over `subjects` (one pattern), file storage, one message kept
  /// per subject (a republished chunk replaces the old one); nullptr with `error` on failure (host).
  std::unique_ptr<NatsStream> createStream(const std::string& name, const std::string& subjects,
                                           QString* error = nullptr);
  /// A reader of the existing stream `name` (viewer: only the stream's message-get API is needed). No round trip.
  std::unique_ptr<NatsStream> bindStream(const std::string& name, QString* error = nullptr);
  /// The server's max_payload (bytes per message), 0 when unknown.
  [[nodiscard]] std::int64_t maxPayload() const;

 private:
  struct Events {
    std::atomic<int> reconnected{0};
  };
  struct Handles;
  NatsConnection();
  std::unique_ptr<Handles> m_handles;
  std::unique_ptr<Events> m_events;  ///< stable address for the cnats callbacks
  std::chrono::milliseconds m_timeout{2000};
};

/// One subscription; destroying it unsubscribes. The handler is not called any more once the destructor returned.
class NatsSubscription {
 public:
  ~NatsSubscription();
  NatsSubscription(const NatsSubscription&) = delete;
  NatsSubscription& operator=(const NatsSubscription&) = delete;
  /// Messages cnats dropped because `pendingMessages` were already waiting (a slow handler).
  [[nodiscard]] std::int64_t dropped() const;

 private:
  friend class NatsConnection;
  struct Handles;
  explicit NatsSubscription(NatsConnection::Handler handler);
  std::unique_ptr<Handles> m_handles;
};

/// A JetStream key-value bucket (history 1).
class NatsKeyValue {
 public:
  ~NatsKeyValue();
  NatsKeyValue(const NatsKeyValue&) = delete;
  NatsKeyValue& operator=(const NatsKeyValue&) = delete;
  /// Stores `value` under `key` and waits for the server's acknowledgement (a round trip).
  bool put(const std::string& key, QByteArrayView value);
  /// The latest value of `key`; nullopt when absent or unreadable. A round trip.
  std::optional<QByteArray> get(const std::string& key);

 private:
  friend class NatsConnection;
  struct Handles;
  NatsKeyValue();
  std::unique_ptr<Handles> m_handles;
};

/// A JetStream stream, used from any thread (cnats' JetStream context is thread-safe); the connection must outlive it.
class NatsStream {
 public:
  ~NatsStream();
  NatsStream(const NatsStream&) = delete;
  NatsStream& operator=(const NatsStream&) = delete;
  /// Publishes `data` on `subject` (one of the stream's) and waits for the stream's acknowledgement (a round trip).
  bool publish(const std::string& subject, QByteArrayView data, QString* error = nullptr);
  /// Why lastMessage() returned nothing.
  enum class Miss { None, Absent, TooLarge, Failed };
  /// The stream's last message on `subject` (a round trip), refused (TooLarge) when it holds more than `maxBytes`.
  /// The message is bounded by the server's max_payload before it is copied.
  std::optional<QByteArray> lastMessage(const std::string& subject, qsizetype maxBytes, Miss* miss = nullptr,
                                        QString* error = nullptr);

 private:
  friend class NatsConnection;
  struct Handles;
  NatsStream();
  std::unique_ptr<Handles> m_handles;
};

/// The subject a key's updates go to: publishing on it (without waiting for an acknowledgement) stores the value.
std::string natsKeySubject(const std::string& bucket, const std::string& key);

/// Called first in main() of every process that may use the relay: OpenSSL then keeps its global state until the
/// process ends instead of freeing it in its own exit handler (OPENSSL_INIT_NO_ATEXIT; the operating system takes the
/// memory back). That handler runs while threads that used OpenSSL may still be ending (cnats' TLS connection
/// threads, std::async workers): freeing under them crashed at exit. Effective only before OpenSSL's first use in
/// the process. Cost: OpenSSL's initialisation, once.
void keepOpenSslStateUntilExit();

/// Releases cnats' library threads and memory and waits (at most 5 s) until its threads have ended
/// (nats_CloseAndWait): once, at process end, after every wrapper is gone. Without the wait, a TLS connection's
/// threads can still be tearing down while OpenSSL's exit handler frees its state (a crash at exit).
void natsShutdown();

}  // namespace sc::session
