#include "app/gui/constraint_editor.h"

#include <algorithm>
#include <utility>

namespace sc::app {

ConstraintEditor::Group ConstraintEditor::painted(spectral::DisplayVertexIds displayed) const {
  spectral::LocatedFullVertices full = m_target.fullVertices(displayed);
  return {std::move(displayed), std::move(full)};
}

bool ConstraintEditor::setSelection(spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors) {
  m_handle = painted(std::move(handle));
  m_anchors = painted(std::move(anchors));
  return edited();
}

bool ConstraintEditor::setHandle(spectral::DisplayVertexIds handle) {
  m_handle = painted(std::move(handle));
  return edited();
}

bool ConstraintEditor::setAnchors(spectral::DisplayVertexIds anchors) {
  m_anchors = painted(std::move(anchors));
  return edited();
}

std::pair<spectral::FullVertexIds, spectral::FullVertexIds> ConstraintEditor::constraints() const {
  const spectral::FullVertexIds& handle = m_handle.full.ids;
  spectral::FullVertexIds anchors = m_anchors.full.ids;
  // a vertex cannot be both: the handle wins
  std::erase_if(anchors,
                [&handle](spectral::FullVertexId id) { return std::binary_search(handle.begin(), handle.end(), id); });
  return {handle, std::move(anchors)};
}

bool ConstraintEditor::edited() {
  if (m_sent) {
    const auto [handle, anchors] = constraints();
    if (handle == m_sentHandle && anchors == m_sentAnchors) return false;  // unchanged: the shape stays as it is
  }
  m_sent = false;
  return send();
}

bool ConstraintEditor::send() {
  if (m_sent || !m_target.canDrag() || m_handle.full.ids.empty()) return false;
  auto [handle, anchors] = constraints();
  m_sent = m_target.sendConstraints(handle, anchors);
  if (m_sent) {  // the host applies it from the shape as it is now
    m_sentHandle = std::move(handle);
    m_sentAnchors = std::move(anchors);
  }
  return m_sent;
}

bool ConstraintEditor::beginDrag() {
  if (!m_target.canDrag() || m_handle.full.ids.empty()) return false;
  if (!m_sent && !send()) return false;
  m_dragging = true;
  return true;
}

bool ConstraintEditor::dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation) {
  if (!m_dragging || !m_target.canDrag()) return false;
  return m_target.sendPose({translation, rotation});
}

void ConstraintEditor::endDrag() {
  if (!m_dragging) return;
  m_dragging = false;
  m_target.endStroke();  // refused without the lock: the host ended the stroke when the lock went
}

void ConstraintEditor::lockChanged(bool held) {
  if (held && !m_hadLock) {
    m_sent = false;
    send();
  }
  if (!held) m_dragging = false;
  m_hadLock = held;
}

void ConstraintEditor::levelChanged() {
  m_handle.displayed = m_target.displayedVertices(m_handle.full);
  m_anchors.displayed = m_target.displayedVertices(m_anchors.full);
}

std::optional<HostConstraints> ConstraintEditor::sent() const {
  if (!m_sent) return std::nullopt;
  return HostConstraints{m_sentHandle, m_sentAnchors};
}

void ConstraintEditor::adopt(const HostConstraints& state, spectral::DisplayVertexIds handle,
                             spectral::DisplayVertexIds anchors) {
  // The state's ids are the truth; where the displayed ids stand for exactly them, their rest positions come along.
  const auto adopted = [this](const spectral::FullVertexIds& ids, spectral::DisplayVertexIds displayed) {
    Group group = painted(std::move(displayed));
    if (group.full.ids != ids) group.full = {ids, {}};
    return group;
  };
  m_handle = adopted(state.handle, std::move(handle));
  m_anchors = adopted(state.anchors, std::move(anchors));
  m_sentHandle = state.handle;
  m_sentAnchors = state.anchors;
  m_sent = true;
}

}  // namespace sc::app
