#pragma once
// One colour per session user (issue 15, presence): deterministic from the peer id, the same on every screen. Used
// for the Peers dock's swatches and for that user's camera marker, pointer and labels in the viewport.

#include <QColor>

#include <cstdint>

namespace sc::app {

/// Colours in the palette; ids beyond it repeat it (peer id p gets entry (p − 1) mod kPeerColorCount).
inline constexpr int kPeerColorCount = 8;

/// The colour of peer `peerId` (1 = the host); kNoPeer (0) gets grey. Cost: O(1).
[[nodiscard]] QColor peerColor(std::uint32_t peerId);

}  // namespace sc::app
