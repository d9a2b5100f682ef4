#pragma once
// SessionHost's per-connection bookkeeping, shared by the host's translation units (session_host*.cpp). Internal:
// not part of the public API.

#include "session/net/session_host.h"

#include <cstdint>
#include <optional>

namespace sc::session {

struct SessionHost::Peer {
  HostPeerConnection* connection = nullptr;  ///< child of the host, deleted (later) when closed
  std::optional<std::uint32_t> waitingFor;   ///< ladder target whose build this peer's transfer waits for
  std::uint32_t transferTarget = 0;          ///< ladder target of the transfer in flight
  std::uint32_t transferVertexCount = 0;     ///< level of the transfer in flight
  std::uint32_t loadedVertexCount = 0;       ///< level of the last completed transfer (0: none yet)
  std::optional<StatsReport> stats;
};

}  // namespace sc::session
