#include "app/gui/viewport/viewport_selection.h"

#include <algorithm>
#include <cstdint>

namespace sc::app {

namespace {

constexpr std::uint8_t kHandleTint[4] = {255, 72, 20, 230};   // orange-red
constexpr std::uint8_t kAnchorTint[4] = {40, 110, 255, 210};  // blue

}  // namespace

void ViewportSelection::set(std::vector<int> handles, std::vector<int> anchors, int vertexCount) {
  for (std::vector<int>* group : {&handles, &anchors}) {
    std::erase_if(*group, [vertexCount](int i) { return i < 0 || i >= vertexCount; });
    std::sort(group->begin(), group->end());
    group->erase(std::unique(group->begin(), group->end()), group->end());
  }
  m_handles = std::move(handles);
  m_anchors = std::move(anchors);
}

void ViewportSelection::clear() {
  m_handles.clear();
  m_anchors.clear();
}

void ViewportSelection::paintTints(ViewportBuffers& buffers, int vertexCount) const {
  std::vector<std::uint8_t>& tints = buffers.writeTints();
  tints.assign(4 * static_cast<std::size_t>(vertexCount), 0);
  for (const auto& [group, tint] : {std::pair{&m_anchors, kAnchorTint}, std::pair{&m_handles, kHandleTint}}) {
    for (const int v : *group) {
      std::copy(tint, tint + 4, tints.begin() + 4 * static_cast<std::ptrdiff_t>(v));
    }
  }
  buffers.gatherProxyTints();
}

bool ViewportSelection::shownBy(const CompactProxy& proxy) const {
  const auto shown = [&proxy](const std::vector<int>& group) {
    return group.empty() || std::any_of(group.begin(), group.end(), [&proxy](int v) { return proxy.uses(v); });
  };
  return proxy.empty() || (shown(m_handles) && shown(m_anchors));
}

}  // namespace sc::app
