#pragma once
// The host's bound on the work of a constraint set (HostEngineOptions::maxConstraintWork, docs/security.md "Hostile
// member"): (handle + anchor ids) · m² ≤ the bound, so that one Constraints message costs the host at most about
// 100 ms of factoring, whatever the mesh. A client fits its set under the bound before sending: handles are kept
// whole and the anchors are thinned to every k-th (k the smallest stride that fits). On a dense mesh the anchors
// are many times the basis size m (a region of a million-vertex scan), so an even subset of them constrains the same
// m-dimensional subspace (issue 19 item 3: the drag of a 1M-vertex mesh anchors about 500k vertices).
// Pure; no Qt.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace sc::session {

/// The default bound: 30000 ids at m = 128 (90–150 ms on one core, a 31 MB ids × m temporary).
inline constexpr double kMaxConstraintWork = 30000.0 * 128.0 * 128.0;

/// The most handle + anchor ids a set of `rows` (m ≥ 1) may have under `maxWork`: ⌊maxWork / m²⌋. O(1).
[[nodiscard]] std::size_t maxConstraintIds(int rows, double maxWork = kMaxConstraintWork);

/// The smallest stride k ≥ 1 such that handleIds + ⌈anchors / k⌉ ≤ maxIds: 1 when the set fits as it is; 0 when the
/// handles alone leave no room (no anchor fits). O(1).
[[nodiscard]] std::size_t anchorStride(std::size_t handleIds, std::size_t anchors, std::size_t maxIds);

/// Keeps anchors[0], anchors[k], anchors[2k], … with k = anchorStride(handleIds, anchors.size(), maxIds) (none when k
/// is 0); returns k. The kept ones stay in their order. O(anchors).
template <class Id>
std::size_t thinAnchors(std::vector<Id>& anchors, std::size_t handleIds, std::size_t maxIds) {
  const std::size_t k = anchorStride(handleIds, anchors.size(), maxIds);
  if (k == 0) {
    anchors.clear();
  } else if (k > 1) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < anchors.size(); i += k) anchors[kept++] = anchors[i];
    anchors.resize(kept);
  }
  return k;
}

}  // namespace sc::session
