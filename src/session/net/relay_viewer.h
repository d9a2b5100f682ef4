#pragma once
// A viewer of the relay (issue 18): a thin adapter that subscribes to a session's frames through NATS without
// connecting to the host, and feeds what arrives to a RelayReceiver (engine/relay_receiver.h, the rules).
//   start(): connect, subscribe to `sc.<sid>.z` (pending limit: a lagging viewer drops old frames, cnats counts
//   them), then read the facts and the keyframe from the bucket (late join: frames that arrived meanwhile wait in
//   the receiver and the newer ones are applied after the keyframe).
// Messages arrive on a cnats thread into a NatsInbox of at most `pendingLimit` messages (the oldest is dropped and
// counted when full: latest wins, a lagging viewer never queues), drained on this object's thread into the
// receiver; the receiver is touched on this object's thread only. cnats reconnects by itself (every 100 ms) and
// resubscribes. Every `statsEvery` the viewer publishes its figures (RelayStats) for the host's aggregate.

#include "session/engine/relay_receiver.h"
#include "session/net/nats_client.h"
#include "session/net/nats_inbox.h"

#include <QtCore/QObject>
#include <QtCore/QString>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

namespace sc::session {

struct RelayViewerOptions {
  NatsConnectOptions nats;
  QString sessionId;
  std::optional<QByteArray> pin;  ///< the host certificate's SHA-256; none: trust the first facts (TOFU)
  int pendingLimit = 8;           ///< frames waiting for this thread, ≥ 1; older ones beyond are dropped
  /// How often the viewer's figures go back to the host on sc.<sid>.stats.<viewer> (0: never).
  std::chrono::milliseconds statsEvery{2000};
  /// Viewers of one thread sharing their signature checks (engine/relay_verified_messages.h; the fan-out
  /// experiment). Null: this viewer verifies every message itself (a real viewer).
  std::shared_ptr<RelayVerifiedMessages> sharedVerification;
};

class RelayViewer final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(RelayViewer)

 public:
  explicit RelayViewer(RelayViewerOptions options, QObject* parent = nullptr);
  ~RelayViewer() override;

  /// Connects, subscribes and joins (facts, keyframe). False with `error` set when the server, the bucket or the
  /// facts cannot be read, or the facts are not the pinned host's.
  bool start(QString* error = nullptr);

  [[nodiscard]] const RelayReceiver& receiver() const { return m_receiver; }
  /// The receiver's figures now.
  [[nodiscard]] RelayViewerStats stats() const;
  /// Frames dropped before the receiver because `pendingLimit` were waiting (in the inbox or in cnats).
  [[nodiscard]] std::int64_t droppedPending() const;
  /// Paused, the viewer stops reading its inbox (a hidden window; tests: a viewer that stops reading): frames pile
  /// up to `pendingLimit` and older ones are dropped. Resuming applies the newest.
  void setPaused(bool paused);
  [[nodiscard]] NatsConnection* connection() const { return m_nats.get(); }

 signals:
  /// Z changed to frame `frame` (receiver().coefficients()).
  void frameApplied(std::uint32_t frame);

 private:
  void drain();
  void publishStats();

  RelayViewerOptions m_options;
  RelayReceiver m_receiver;
  std::unique_ptr<NatsConnection> m_nats;
  std::unique_ptr<NatsKeyValue> m_kv;
  std::unique_ptr<NatsSubscription> m_subscription;
  NatsInbox m_inbox;
  std::uint64_t m_viewerId;  ///< random, names this viewer's statistics subject
  bool m_paused = false;
};

}  // namespace sc::session
