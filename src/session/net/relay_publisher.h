#pragma once
// The host's side of the relay (issue 18; docs/protocol.md, "Relay through NATS"): a thin adapter that follows a
// started SessionHost and publishes through a NATS server, once per frame whatever the number of viewers:
//   - every frame, signed (relay_message.h), on `sc.<sid>.z`;
//   - the latest frame as the keyframe, KV bucket `sc_<sid>` key `keyframe`: every `keyframeEvery` frames and
//     200 ms after the last frame (so a still shape is stored exactly), published on the key's subject without
//     waiting for the acknowledgement (the Qt thread never waits on the broker per frame);
//   - the session facts (m, vertex count, the host certificate) under key `session`, at start();
// and it reads the viewers' figures from `sc.<sid>.stats.>` (RelayAudience: one aggregate, not one row per viewer;
// at most 1,024 messages wait, the excess is dropped).
// Level payloads are not published: viewers that need a level fetch it from the host (or, headless, use Z alone).
// Editors are unaffected: they stay on TLS + UDP. cnats buffers publishes while it reconnects.

#include "session/engine/relay_audience.h"
#include "session/net/nats_client.h"
#include "session/net/nats_inbox.h"
#include "session/wire/relay_message.h"

#include <QtCore/QObject>
#include <QtCore/QString>

#include <cstdint>
#include <memory>
#include <string>

class QTimer;

namespace sc::session {

class SessionHost;

struct RelayPublisherOptions {
  NatsConnectOptions nats;
  QString sessionId;       ///< isValidSessionId()
  int keyframeEvery = 30;  ///< frames between two stored keyframes while the shape moves, ≥ 1
};

/// The broker's side of a relay: made by RelayPublisher::connectToBroker() on any thread, handed to start().
struct RelayBrokerLink {
  std::unique_ptr<NatsConnection> nats;
  std::unique_ptr<NatsKeyValue> kv;  ///< the session's bucket (destroyed before the connection it uses)
  QString sessionId;                 ///< whose bucket it is (start() refuses another session's link)
  QString error;                     ///< why not, when nats or kv is null
};

/// What the publisher sent.
struct RelayPublisherCounters {
  std::int64_t frames = 0;     ///< frames published on the frame subject
  std::int64_t keyframes = 0;  ///< keyframes stored
  std::int64_t bytes = 0;      ///< payload bytes published (frames and keyframes)
  std::int64_t failures = 0;   ///< publishes cnats refused
};

class RelayPublisher final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(RelayPublisher)

 public:
  /// @param host  started (its identity is known) and outliving this publisher.
  RelayPublisher(SessionHost& host, RelayPublisherOptions options, QObject* parent = nullptr);
  ~RelayPublisher() override;

  /// Connects to `options`' broker and creates the session's bucket. Blocks (the connection up to its timeout, 2 s
  /// by default, per URL, then a JetStream request up to the same timeout): call it off a GUI thread. Thread-safe;
  /// touches no publisher.
  static RelayBrokerLink connectToBroker(const RelayPublisherOptions& options);

  /// Connects, creates the bucket, stores the facts and the current shape as the keyframe, then follows the host's
  /// frames. False with `error` set when any of it fails. Same as start(connectToBroker(options), error).
  bool start(QString* error = nullptr);
  /// start() with the broker link made beforehand (on a worker, so that the caller's thread never waits on the
  /// broker's connect); `link` is taken also when it failed (its error is reported).
  bool start(RelayBrokerLink link, QString* error = nullptr);
  [[nodiscard]] const RelayPublisherCounters& counters() const { return m_counters; }
  [[nodiscard]] NatsConnection* connection() const { return m_nats.get(); }
  [[nodiscard]] std::string frameSubject() const;
  /// The viewers that reported within the last 10 s, aggregated.
  [[nodiscard]] RelayAudienceSummary audience() const;

 private:
  /// Checks the session id and the host's identity and makes the signer; false with `error` set.
  bool makeSigner(QString* error);
  void onFrame(std::uint32_t frame);
  void storeKeyframe();
  void drainStats();
  [[nodiscard]] QByteArray signedFrame() const;

  SessionHost& m_host;
  RelayPublisherOptions m_options;
  std::string m_bucket;
  std::unique_ptr<RelaySigner> m_signer;
  std::unique_ptr<NatsConnection> m_nats;
  std::unique_ptr<NatsKeyValue> m_kv;
  std::unique_ptr<NatsSubscription> m_statsSubscription;
  NatsInbox m_statsInbox;
  RelayAudience m_audience;
  QTimer* m_keyframeTimer = nullptr;  ///< single-shot: the keyframe after the last frame
  std::uint32_t m_storedFrame = 0;
  bool m_stored = false;
  int m_sinceKeyframe = 0;
  RelayPublisherCounters m_counters;
};

/// The frame subject of a session, `sc.<sid>.z`, and its bucket, `sc_<sid>`.
std::string relayFrameSubject(const QString& sessionId);
std::string relayBucket(const QString& sessionId);
/// A viewer's statistics subject, `sc.<sid>.stats.<viewer as 16 hex digits>`.
std::string relayStatsSubject(const QString& sessionId, std::uint64_t viewer);

}  // namespace sc::session
