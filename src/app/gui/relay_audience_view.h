#pragma once
// How the host's docks show its viewers through NATS (issue 18 item 3): ONE row in the Peers table and one section
// in the Statistics dock for the whole audience, whatever its size (a thousand viewers are one row, never a thousand).
// Pure formatting of a session::RelayAudienceSummary; no widgets.

#include "model/peer_table_model.h"
#include "session/engine/relay_audience.h"

#include <QString>

#include <cstdint>

namespace sc::app {

/// The peerId of the audience row: no peer has it (peer ids are below 128).
inline constexpr std::uint32_t kRelayAudienceRowId = 0xFFFFFFFFu;

/// "N viewers through NATS": Loss % is the median viewer's loss, Delay ms the median of the viewers' own p99
/// latencies; the figure cells' tooltip gives the distributions (median, p90, max). No figures while no viewer
/// reported.
model::PeerRow relayAudienceRow(const session::RelayAudienceSummary& audience);

/// The Statistics dock's relay section: count, loss and latency distributions, forged frames the viewers dropped.
QString relayAudienceText(const session::RelayAudienceSummary& audience);

}  // namespace sc::app
