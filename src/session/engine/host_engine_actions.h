#pragma once
// What a HostEngine asks its adapter to do (host_engine.h): a list of actions, carried out in order, and the time
// at which the engine wants its next tick(). Plain values: no sockets, no Qt objects. The adapter sends messages,
// encodes frames, starts transfers from its level cache, closes connections and emits its signals; it decides
// nothing itself.

#include "session/engine/receiver_statistics.h"
#include "session/wire/control_messages.h"
#include "session/wire/lock_messages.h"

#include <Eigen/Core>
#include <QtCore/QString>

#include <cstdint>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

namespace sc::spectral {
struct ConstraintSet;
}

namespace sc::session {

/// Bytes the host queues for one peer at most (4 × the transfer high water): above, the peer is dropped.
inline constexpr std::int64_t kSendBudgetBytes = 1 << 20;

/// What the adapter measured of one connection's outgoing queue (bytes accepted by send() not yet taken by the
/// kernel, TLS records included).
struct SendQueueReport {
  std::int64_t queuedBytes = 0;
  std::int64_t peakBytes = 0;  ///< the largest queue since the connection opened
  Micros lastDrained{0};       ///< when the kernel last took bytes, or the queue was last seen empty
  bool overBudget = false;     ///< the adapter refused a write that would have passed sendBudgetBytes
};

/// One control message to one welcomed peer.
struct SendToPeer {
  PeerId peer = kNoPeer;
  ControlMessage message;
};

/// One control message to every welcomed peer (encoded once).
struct SendToAll {
  ControlMessage message;
};

/// One coefficient frame to encode and send on the datagram channel, then frameSent(frame).
struct SendFrame {
  std::uint32_t frame = 0;
  std::shared_ptr<const Eigen::MatrixXd> Z;  ///< m by 3, immutable (shared with the engine)
  Micros stamp{0};                           ///< the datagram's timestamp: the drag's arrival, else the send time
  bool still = false;                        ///< a still frame (same Z as the moving frame before it)
};

/// Start a model transfer of the built level `target` to `peer` (ModelBegin with `transferId`, then chunks).
struct StartTransfer {
  PeerId peer = kNoPeer;
  std::uint32_t transferId = 0;
  std::uint32_t target = 0;
};

/// Build the level `target` (explicitly wanted: before the prefetch); the adapter answers with onLevelReady() or
/// onLevelFailed().
struct RequestLevel {
  std::uint32_t target = 0;
};

/// Build the rest of the ladder in the background (each answered like RequestLevel).
struct PrefetchLevels {};

/// Factor a member's accepted constraint set off the network thread: run HostEngine::deformer().prepare() on it (a
/// const call that reads only immutable data, safe while the engine solves) on a worker, then answer
/// onConstraintsPrepared(ticket, result) on the engine's thread. The engine holds that member's drag frames until then.
struct PrepareConstraints {
  std::uint64_t ticket = 0;
  std::shared_ptr<const spectral::ConstraintSet> constraints;  ///< never null
};

/// Close a connection: Graceful flushes what is queued first, Abort drops it at once. Either way the adapter
/// answers with onClosed() once the connection is gone.
struct ClosePeer {
  enum class How : std::uint8_t { Graceful, Abort };
  PeerId peer = kNoPeer;
  How how = How::Graceful;
};

/// A connection's handshake ran past its deadline: the adapter ticks its HostHandshake (which refuses and closes).
struct ExpireHandshake {
  PeerId peer = kNoPeer;
};

/// Signals for the adapter's observers.
struct PeersChanged {};
struct LockChanged {};
/// The session's edit history changed (HostEngine::history()); its log went to every peer already.
struct EditHistoryChanged {};
struct StatsReported {
  PeerId peer = kNoPeer;
  StatsReport report;
};
struct LogLine {
  QString text;
};
/// A member's Presence (author = its peer id), for the host's own user's view.
struct PresenceReceived {
  Presence presence;
};

using HostAction = std::variant<SendToPeer, SendToAll, SendFrame, StartTransfer, RequestLevel, PrefetchLevels,
                                PrepareConstraints, ClosePeer, ExpireHandshake, PeersChanged, LockChanged,
                                EditHistoryChanged, StatsReported, LogLine, PresenceReceived>;

struct HostActions {
  std::vector<HostAction> list;  ///< in order
  /// When the engine wants tick() next (session clock); nullopt: never (not started, or shut down).
  std::optional<Micros> wakeAt;

  template <typename T>
  void add(T action) {
    list.emplace_back(std::move(action));
  }
};

}  // namespace sc::session
