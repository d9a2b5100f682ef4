#include "session/net/nats_client.h"

#include <QtCore/QFile>
#include <QtCore/QStringList>

#include <nats/nats.h>
#include <openssl/crypto.h>

#include <algorithm>
#include <cstdint>
#include <future>
#include <utility>

namespace sc::session {
namespace {

/// The connection's JetStream context, made once: its requests wait `timeout` (the connect timeout; cnats' default
/// would be 5 s).
natsStatus jetStreamOf(jsCtx** js, natsConnection* connection, std::chrono::milliseconds timeout) {
  if (*js != nullptr) return NATS_OK;
  jsOptions options;
  natsStatus s = jsOptions_Init(&options);
  options.Wait = timeout.count();
  if (s == NATS_OK) s = natsConnection_JetStream(js, connection, &options);
  return s;
}

/// How long natsShutdown() waits for cnats' threads to end (a TLS connection's threads must be gone before OpenSSL's
/// exit handler frees its state).
constexpr std::int64_t kShutdownWaitMs = 5000;

QString statusText(natsStatus status) {
  const char* last = nats_GetLastError(nullptr);
  const QString text = QString::fromUtf8(natsStatus_GetText(status));
  return last && *last ? text + QStringLiteral(": ") + QString::fromUtf8(last) : text;
}

void onReconnected(natsConnection* /*connection*/, void* closure) {
  static_cast<std::atomic<int>*>(closure)->fetch_add(1);
}

/// Why connecting failed, in words a user can act on (the URL, the user, TLS), with cnats' text in parentheses.
QString connectFailureText(natsStatus status, const NatsConnectOptions& options) {
  const QString details = statusText(status);
  switch (status) {
    case NATS_CONNECTION_AUTH_FAILED:
    case NATS_NOT_PERMITTED:
      return QStringLiteral("the NATS server at %1 refused the user \u201c%2\u201d or its password (%3)")
          .arg(options.url, options.user, details);
    case NATS_NO_SERVER:
      return QStringLiteral("no NATS server answered at %1 (%2)").arg(options.url, details);
    case NATS_SSL_ERROR:
      return QStringLiteral(
                 "TLS to the NATS server at %1 failed: its certificate is not signed by the trusted CA%2 or does not "
                 "name the server (%3)")
          .arg(options.url,
               options.caFile.isEmpty() ? QStringLiteral(" (the system's; give the broker's CA file)")
                                        : QStringLiteral(" in %1").arg(options.caFile),
               details);
    case NATS_SECURE_CONNECTION_REQUIRED:
      return QStringLiteral("the NATS server at %1 requires TLS: use a tls:// URL (%2)").arg(options.url, details);
    case NATS_SECURE_CONNECTION_WANTED:
      return QStringLiteral("the NATS server at %1 does not offer TLS: use a nats:// URL (%2)")
          .arg(options.url, details);
    default:
      return details;
  }
}

/// TLS options: the trusted CA file and tls:// URLs. NATS_OK when none apply. cnats itself switches to TLS when the
/// server requires it, and checks that the certificate names the URL's host (a DNS name, or an IP address against
/// the certificate's IP entries): natsOptions_SetExpectedHostname is not needed.
natsStatus setTls(natsOptions* opts, const NatsConnectOptions& options, QString* error) {
  natsStatus s = NATS_OK;
  if (!options.caFile.isEmpty()) {
    s = natsOptions_LoadCATrustedCertificates(opts, QFile::encodeName(options.caFile).constData());
    if (s != NATS_OK) {
      if (error) *error = QStringLiteral("cannot load the CA file %1 (%2)").arg(options.caFile, statusText(s));
      return s;
    }
  }
  if (natsUrlWantsTls(options.url)) s = natsOptions_SetSecure(opts, true);
  if (s != NATS_OK && error) *error = statusText(s);
  return s;
}

struct OptionsDeleter {
  void operator()(natsOptions* options) const { natsOptions_Destroy(options); }
};

}  // namespace

struct NatsConnection::Handles {
  natsConnection* connection = nullptr;
  jsCtx* js = nullptr;
  ~Handles() {
    if (js) jsCtx_Destroy(js);
    if (connection) natsConnection_Destroy(connection);  // closes it first
  }
};

struct NatsSubscription::Handles {
  natsSubscription* subscription = nullptr;
  NatsConnection::Handler handler;
  std::promise<void> completed;  ///< set by cnats once the subscription closed and its handler returned
  bool completionArmed = false;
  ~Handles() {
    if (!subscription) return;
    natsSubscription_Unsubscribe(subscription);
    // A handler running now must return before `handler` is destroyed (natsSubscription_SetOnCompleteCB); bounded,
    // in case the connection is already closed.
    if (completionArmed) completed.get_future().wait_for(std::chrono::seconds(2));
    natsSubscription_Destroy(subscription);
  }
};

struct NatsKeyValue::Handles {
  kvStore* kv = nullptr;
  ~Handles() {
    if (kv) kvStore_Destroy(kv);
  }
};

NatsConnection::NatsConnection() : m_handles(std::make_unique<Handles>()), m_events(std::make_unique<Events>()) {}
NatsConnection::~NatsConnection() = default;

std::unique_ptr<NatsConnection> NatsConnection::connect(const NatsConnectOptions& options, QString* error) {
  natsOptions* raw = nullptr;
  if (natsOptions_Create(&raw) != NATS_OK) {
    if (error) *error = QStringLiteral("cannot create NATS options");
    return nullptr;
  }
  const std::unique_ptr<natsOptions, OptionsDeleter> opts(raw);
  std::unique_ptr<NatsConnection> out(new NatsConnection());
  out->m_timeout = options.timeout;
  const QByteArray url = options.url.toUtf8();
  const QByteArray user = options.user.toUtf8();
  const QByteArray password = options.password.toUtf8();
  const QByteArray name = options.name.toUtf8();
  natsStatus s = natsOptions_SetURL(opts.get(), url.constData());
  if (s == NATS_OK && !user.isEmpty()) s = natsOptions_SetUserInfo(opts.get(), user.constData(), password.constData());
  if (s == NATS_OK && !name.isEmpty()) s = natsOptions_SetName(opts.get(), name.constData());
  if (s == NATS_OK) s = natsOptions_SetTimeout(opts.get(), options.timeout.count());
  if (s == NATS_OK) s = natsOptions_SetMaxReconnect(opts.get(), -1);
  if (s == NATS_OK) s = natsOptions_SetReconnectWait(opts.get(), options.reconnectWait.count());
  if (s == NATS_OK) s = natsOptions_SetReconnectJitter(opts.get(), 0, 0);
  if (s == NATS_OK) s = natsOptions_SetReconnectedCB(opts.get(), onReconnected, &out->m_events->reconnected);
  if (s == NATS_OK && options.retryOnFailedConnect) {
    s = natsOptions_SetRetryOnFailedConnect(opts.get(), true, nullptr, nullptr);
  }
  if (s != NATS_OK) {
    if (error) *error = statusText(s);
    return nullptr;
  }
  if (setTls(opts.get(), options, error) != NATS_OK) return nullptr;
  s = natsConnection_Connect(&out->m_handles->connection, opts.get());
  if (s == NATS_NOT_YET_CONNECTED && options.retryOnFailedConnect) s = NATS_OK;
  if (s != NATS_OK) {
    if (error) *error = connectFailureText(s, options);
    return nullptr;
  }
  return out;
}

bool natsUrlWantsTls(const QString& urls) {
  const QStringList list = urls.split(QLatin1Char(','));
  return std::any_of(list.begin(), list.end(), [](const QString& url) {
    return url.trimmed().startsWith(QStringLiteral("tls://"), Qt::CaseInsensitive);
  });
}

bool NatsConnection::publish(const std::string& subject, QByteArrayView data) {
  return natsConnection_Publish(m_handles->connection, subject.c_str(), data.data(), static_cast<int>(data.size())) ==
         NATS_OK;
}

bool NatsConnection::flush(std::chrono::milliseconds timeout) {
  return natsConnection_FlushTimeout(m_handles->connection, timeout.count()) == NATS_OK;
}

QString NatsConnection::lastError() const {
  const char* text = nullptr;
  natsConnection_GetLastError(m_handles->connection, &text);
  return text ? QString::fromUtf8(text) : QString();
}

bool NatsConnection::connected() const {
  return natsConnection_Status(m_handles->connection) == NATS_CONN_STATUS_CONNECTED;
}

NatsTraffic NatsConnection::traffic() const {
  NatsTraffic out;
  natsStatistics* stats = nullptr;
  if (natsStatistics_Create(&stats) != NATS_OK) return out;
  if (natsConnection_GetStats(m_handles->connection, stats) == NATS_OK) {
    natsStatistics_GetCounts(stats, &out.inMessages, &out.inBytes, &out.outMessages, &out.outBytes, &out.reconnects);
  }
  natsStatistics_Destroy(stats);
  return out;
}

namespace {
void onComplete(void* closure) { static_cast<std::promise<void>*>(closure)->set_value(); }

void onMessage(natsConnection* /*connection*/, natsSubscription* /*subscription*/, natsMsg* message, void* closure) {
  const auto& handler = *static_cast<const NatsConnection::Handler*>(closure);
  handler(QByteArrayView(natsMsg_GetData(message), natsMsg_GetDataLength(message)));
  natsMsg_Destroy(message);
}
}  // namespace

NatsSubscription::NatsSubscription(NatsConnection::Handler handler) : m_handles(std::make_unique<Handles>()) {
  m_handles->handler = std::move(handler);
}
NatsSubscription::~NatsSubscription() = default;

std::int64_t NatsSubscription::dropped() const {
  int64_t count = 0;
  natsSubscription_GetDropped(m_handles->subscription, &count);
  return count;
}

std::unique_ptr<NatsSubscription> NatsConnection::subscribe(const std::string& subject, int pendingMessages,
                                                            Handler handler, QString* error) {
  std::unique_ptr<NatsSubscription> out(new NatsSubscription(std::move(handler)));
  natsStatus s = natsConnection_Subscribe(&out->m_handles->subscription, m_handles->connection, subject.c_str(),
                                          onMessage, &out->m_handles->handler);
  if (s == NATS_OK) {
    s = natsSubscription_SetOnCompleteCB(out->m_handles->subscription, onComplete, &out->m_handles->completed);
    out->m_handles->completionArmed = s == NATS_OK;
  }
  // Bytes: generous (a frame of kMaxRows rows is ≈ 98 kB); the message count is the limit that matters.
  if (s == NATS_OK) s = natsSubscription_SetPendingLimits(out->m_handles->subscription, pendingMessages, 64 << 20);
  if (s == NATS_OK) s = natsConnection_FlushTimeout(m_handles->connection, m_timeout.count());
  if (s != NATS_OK) {
    if (error) *error = statusText(s);
    return nullptr;
  }
  return out;
}

NatsKeyValue::NatsKeyValue() : m_handles(std::make_unique<Handles>()) {}
NatsKeyValue::~NatsKeyValue() = default;

std::unique_ptr<NatsKeyValue> NatsConnection::createBucket(const std::string& bucket, QString* error) {
  natsStatus s = jetStreamOf(&m_handles->js, m_handles->connection, m_timeout);
  std::unique_ptr<NatsKeyValue> out(new NatsKeyValue());
  kvConfig config;
  if (s == NATS_OK) s = kvConfig_Init(&config);
  config.Bucket = bucket.c_str();
  config.History = 1;
  if (s == NATS_OK) s = js_CreateKeyValue(&out->m_handles->kv, m_handles->js, &config);
  if (s != NATS_OK) {
    if (error) *error = statusText(s);
    return nullptr;
  }
  return out;
}

std::unique_ptr<NatsKeyValue> NatsConnection::bindBucket(const std::string& bucket, QString* error) {
  natsStatus s = jetStreamOf(&m_handles->js, m_handles->connection, m_timeout);
  std::unique_ptr<NatsKeyValue> out(new NatsKeyValue());
  if (s == NATS_OK) s = js_KeyValue(&out->m_handles->kv, m_handles->js, bucket.c_str());
  if (s != NATS_OK) {
    if (error) *error = statusText(s);
    return nullptr;
  }
  return out;
}

bool NatsKeyValue::put(const std::string& key, QByteArrayView value) {
  uint64_t revision = 0;
  return kvStore_Put(&revision, m_handles->kv, key.c_str(), value.data(), static_cast<int>(value.size())) == NATS_OK;
}

std::optional<QByteArray> NatsKeyValue::get(const std::string& key) {
  kvEntry* entry = nullptr;
  if (kvStore_Get(&entry, m_handles->kv, key.c_str()) != NATS_OK || !entry) return std::nullopt;
  QByteArray value(static_cast<const char*>(kvEntry_Value(entry)), kvEntry_ValueLen(entry));
  kvEntry_Destroy(entry);
  return value;
}

struct NatsStream::Handles {
  jsCtx* js = nullptr;  ///< the connection's, not owned
  std::string name;
};

NatsStream::NatsStream() : m_handles(std::make_unique<Handles>()) {}
NatsStream::~NatsStream() = default;

std::int64_t NatsConnection::maxPayload() const { return natsConnection_GetMaxPayload(m_handles->connection); }

std::unique_ptr<NatsStream> NatsConnection::bindStream(const std::string& name, QString* error) {
  const natsStatus s = jetStreamOf(&m_handles->js, m_handles->connection, m_timeout);
  if (s != NATS_OK) {
    if (error) *error = statusText(s);
    return nullptr;
  }
  std::unique_ptr<NatsStream> out(new NatsStream());
  out->m_handles->js = m_handles->js;
  out->m_handles->name = name;
  return out;
}

std::unique_ptr<NatsStream> NatsConnection::createStream(const std::string& name, const std::string& subjects,
                                                         QString* error) {
  std::unique_ptr<NatsStream> out = bindStream(name, error);
  if (!out) return nullptr;
  jsStreamConfig config;
  natsStatus s = jsStreamConfig_Init(&config);
  const char* subjectList[] = {subjects.c_str()};
  config.Name = name.c_str();
  config.Subjects = subjectList;
  config.SubjectsLen = 1;
  config.MaxMsgsPerSubject = 1;
  config.Storage = js_FileStorage;
  jsStreamInfo* info = nullptr;
  jsErrCode code = static_cast<jsErrCode>(0);
  if (s == NATS_OK) s = js_AddStream(&info, m_handles->js, &config, nullptr, &code);
  if (s != NATS_OK && code == JSStreamNameExistErr) s = js_UpdateStream(&info, m_handles->js, &config, nullptr, &code);
  if (info) jsStreamInfo_Destroy(info);
  if (s != NATS_OK) {
    if (error) *error = statusText(s);
    return nullptr;
  }
  return out;
}

bool NatsStream::publish(const std::string& subject, QByteArrayView data, QString* error) {
  jsPubAck* ack = nullptr;
  const natsStatus s =
      js_Publish(&ack, m_handles->js, subject.c_str(), data.data(), static_cast<int>(data.size()), nullptr, nullptr);
  if (ack) jsPubAck_Destroy(ack);
  if (s != NATS_OK && error) *error = statusText(s);
  return s == NATS_OK;
}

std::optional<QByteArray> NatsStream::lastMessage(const std::string& subject, qsizetype maxBytes, Miss* miss,
                                                  QString* error) {
  natsMsg* message = nullptr;
  jsErrCode code = static_cast<jsErrCode>(0);
  const natsStatus s = js_GetLastMsg(&message, m_handles->js, m_handles->name.c_str(), subject.c_str(), nullptr, &code);
  if (s != NATS_OK || !message) {
    if (message) natsMsg_Destroy(message);
    if (miss) *miss = s == NATS_NOT_FOUND || code == JSNoMessageFoundErr ? Miss::Absent : Miss::Failed;
    if (error) *error = statusText(s);
    return std::nullopt;
  }
  const int size = natsMsg_GetDataLength(message);
  std::optional<QByteArray> out;
  if (size <= maxBytes) {
    out.emplace(natsMsg_GetData(message), size);
    if (miss) *miss = Miss::None;
  } else {
    if (miss) *miss = Miss::TooLarge;
    if (error) *error = QStringLiteral("%1 bytes, at most %2 expected").arg(size).arg(maxBytes);
  }
  natsMsg_Destroy(message);
  return out;
}

std::string natsKeySubject(const std::string& bucket, const std::string& key) { return "$KV." + bucket + "." + key; }

void keepOpenSslStateUntilExit() { OPENSSL_init_crypto(OPENSSL_INIT_NO_ATEXIT, nullptr); }

void natsShutdown() { nats_CloseAndWait(kShutdownWaitMs); }

}  // namespace sc::session
