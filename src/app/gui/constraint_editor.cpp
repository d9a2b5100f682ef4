#include "app/gui/constraint_editor.h"

#include <algorithm>
#include <utility>

namespace sc::app {

bool ConstraintEditor::setSelection(spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors) {
  m_handle = std::move(handle);
  m_anchors = std::move(anchors);
  m_sent = false;
  return send();
}

bool ConstraintEditor::setHandle(spectral::DisplayVertexIds handle) {
  return setSelection(std::move(handle), std::move(m_anchors));
}

bool ConstraintEditor::setAnchors(spectral::DisplayVertexIds anchors) {
  return setSelection(std::move(m_handle), std::move(anchors));
}

bool ConstraintEditor::send() {
  if (m_sent || !m_target.canDrag()) return false;
  const spectral::FullVertexIds handle = m_target.fullIds(m_handle);
  if (handle.empty()) return false;
  spectral::FullVertexIds anchors = m_target.fullIds(m_anchors);
  // a vertex cannot be both: the handle wins
  std::erase_if(anchors,
                [&handle](spectral::FullVertexId id) { return std::binary_search(handle.begin(), handle.end(), id); });
  m_sent = m_target.sendConstraints(handle, anchors);
  if (m_sent) {  // the host applies it from the shape as it is now
    m_sentHandle = handle;
    m_sentAnchors = std::move(anchors);
  }
  return m_sent;
}

bool ConstraintEditor::beginDrag() {
  if (!m_target.canDrag() || m_handle.empty()) return false;
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

void ConstraintEditor::clear() {
  m_sent = false;
  m_handle.clear();
  m_anchors.clear();
}

std::optional<HostConstraints> ConstraintEditor::sent() const {
  if (!m_sent) return std::nullopt;
  return HostConstraints{m_sentHandle, m_sentAnchors};
}

void ConstraintEditor::adopt(const HostConstraints& state, spectral::DisplayVertexIds handle,
                             spectral::DisplayVertexIds anchors) {
  m_handle = std::move(handle);
  m_anchors = std::move(anchors);
  m_sentHandle = state.handle;
  m_sentAnchors = state.anchors;
  m_sent = true;
}

}  // namespace sc::app
