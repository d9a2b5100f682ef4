#pragma once
// ViewportSelection: the handle and anchor vertices a MeshViewport shows, and their vertex tints (handles
// orange-red over anchors blue) written into ViewportBuffers.

#include "app/gui/viewport/viewport_buffers.h"

#include <vector>

namespace sc::app {

class ViewportSelection {
 public:
  /// Replaces both groups: indices outside [0, vertexCount) are dropped, the rest sorted and de-duplicated.
  void set(std::vector<int> handles, std::vector<int> anchors, int vertexCount);
  void clear();
  [[nodiscard]] const std::vector<int>& handles() const { return m_handles; }
  [[nodiscard]] const std::vector<int>& anchors() const { return m_anchors; }
  /// The handles (true) or the anchors, for a brush to edit (keep them sorted and unique).
  [[nodiscard]] std::vector<int>& group(bool handles) { return handles ? m_handles : m_anchors; }

  /// Writes the tints of `vertexCount` vertices into `buffers` (RGBA, A = tint strength; a vertex in both groups
  /// shows as a handle), the proxy's gathered from them. Cost: O(#V + #P).
  void paintTints(ViewportBuffers& buffers, int vertexCount) const;
  /// Whether `proxy` is empty or keeps at least one vertex of each non-empty group. Cost: O(#handles + #anchors).
  [[nodiscard]] bool shownBy(const CompactProxy& proxy) const;

 private:
  std::vector<int> m_handles;
  std::vector<int> m_anchors;
};

}  // namespace sc::app
