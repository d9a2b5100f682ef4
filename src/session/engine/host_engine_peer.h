#pragma once
// HostEngine's per-connection bookkeeping (HostEngine::Peer), shared by the engine's translation units
// (host_engine*.cpp). Internal: not part of the public API. It needs only wire types and the clock, so it includes
// nothing of the engine (no include loop with host_engine.h).

#include "session/engine/host_engine_rate_limit.h"
#include "session/wire/control_messages.h"
#include "session/wire/lock_messages.h"

#include <QtCore/QString>

#include <cstdint>
#include <optional>
#include <string>

namespace sc::session {

struct HostEnginePeer {
  PeerId id = kNoPeer;
  std::string address;   ///< the admission limits' key (e.g. the IP address as text)
  Millis acceptedAt{0};  ///< the handshake deadline counts from here
  Millis lastHeard{0};   ///< the last byte received (or the accept)
  bool welcomed = false;
  bool closing = false;                     ///< asked to close or refused: no longer counted, listed or sent to
  QString name;                             ///< set once welcomed
  std::optional<std::uint32_t> waitingFor;  ///< ladder target whose build this peer's transfer waits for
  bool transferring = false;                ///< a transfer is in flight (StartTransfer until onTransferFinished)
  std::uint32_t transferTarget = 0;         ///< ladder target of the transfer in flight
  std::uint32_t transferVertexCount = 0;    ///< level of the transfer in flight
  std::uint32_t loadedVertexCount = 0;      ///< level of the last completed transfer (0: none yet)
  std::optional<StatsReport> stats;
  TokenBucket messages;            ///< every message after the Welcome
  TokenBucket lockRequests;        ///< LockRequest{Request}
  TokenBucket resolutionRequests;  ///< ResolutionRequest
  TokenBucket constraints;         ///< Constraints
  TokenBucket editRequests;        ///< EditRequest (undo / redo)
  TokenBucket presence;            ///< Presence (relayed within the rate, dropped over it)
  /// The latest request over its rate, served when the rate allows (housekeeping): an honest client's last word is
  /// never lost, and a flood costs one stored message per peer.
  std::optional<ResolutionRequest> deferredResolution;
  std::optional<Constraints> deferredConstraints;

  [[nodiscard]] bool member() const { return welcomed && !closing; }
};

}  // namespace sc::session
