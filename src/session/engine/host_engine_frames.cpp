// HostEngine: frame production (solve the pending pose, send the coefficient frame), the still frame after the
// last moving frame (still_frame_schedule.h) and Keyframes.

#include "session/engine/host_engine.h"

#include <algorithm>

namespace sc::session {

void HostEngine::produceFrame(Micros now, bool still, HostActions& out, bool jumped) {
  if (m_shutDown) return;
  Micros stamp = now;
  bool moved = jumped;
  if (m_pendingArrival && !m_constraintsInFlight) {  // poses wait for their constraints' factorisation
    Eigen::MatrixXd Z = m_deformer->solve(combinedPoses());
    moved = Z != *m_Z;
    m_Z = std::make_shared<const Eigen::MatrixXd>(std::move(Z));
    stamp = *m_pendingArrival;
    m_pendingArrival.reset();
    m_lastDragFrameAt = now;
  }
  ++m_frame;
  out.add(SendFrame{m_frame, m_Z, stamp, still});
  m_lastFrameAt = now;
  ++m_counters.framesSent;
  m_stillDue.reset();
  if (const std::optional<Micros> due = m_stillSchedule.onFrame(now, moved); due && m_options.stillFrame) {
    m_stillDue = now + std::max<Micros>(Millis{1}, std::chrono::ceil<Millis>(*due - now));
  }
  if (m_options.referenceEvery > 0 && ++m_framesSinceKeyframe >= m_options.referenceEvery) {
    m_framesSinceKeyframe = 0;
    for (const auto& [id, peer] : m_peers) {
      if (peer.loadedVertexCount > 0 && !peer.closing) sendKeyframe(id, out);
    }
  }
}

void HostEngine::produceStillFrame(Micros now, HostActions& out) {
  // A drag that came in meanwhile sends its own (moving) frame: no still frame then.
  if (m_shutDown || m_coalesceDue || m_pendingArrival) return;
  ++m_counters.stillFramesSent;
  produceFrame(now, true, out);
}

void HostEngine::sendKeyframe(PeerId peer, HostActions& out) {
  const Eigen::MatrixXd& Z = *m_Z;
  Keyframe keyframe;
  keyframe.frame = m_frame;
  keyframe.z.resize(static_cast<std::size_t>(Z.rows()) * 3);
  for (Eigen::Index r = 0; r < Z.rows(); ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) keyframe.z[static_cast<std::size_t>(3 * r + c)] = Z(r, c);
  }
  out.add(SendToPeer{peer, std::move(keyframe)});
  ++m_counters.keyframesSent;
}

}  // namespace sc::session
