// SessionHost: frame production (solve the pending pose, send the coefficient frame), the still frame after the
// last moving frame (still_frame_schedule.h) and Keyframes.

#include "session/net/session_host.h"

#include "session/net/host_datagram_channel.h"
#include "session/net/host_peer_connection.h"
#include "session/engine/session_clock.h"
#include "session/net/session_host_peer.h"

#include <QtCore/QTimer>

#include <algorithm>

namespace sc::session {

// --- frames

void SessionHost::produceFrame() {
  if (m_shutDown) return;
  const Micros t = sessionNow();
  Micros stamp = t;
  bool moved = false;
  if (m_pendingArrival) {
    Eigen::MatrixXd Z = m_deformer->solve(m_pendingPoses);
    moved = Z != m_Z;
    m_Z = std::move(Z);
    stamp = *m_pendingArrival;
    m_pendingArrival.reset();
    m_lastDragFrameAt = t;
  }
  ++m_frame;
  m_channel->sendFrame(m_frame, m_Z, stamp);
  m_lastFrameAt = t;
  ++m_counters.framesSent;
  m_still->stop();
  if (const std::optional<Micros> due = m_stillSchedule.onFrame(t, moved); due && m_options.stillFrame) {
    const auto wait = std::chrono::ceil<Millis>(*due - sessionNow());
    m_still->start(std::max<int>(1, static_cast<int>(wait.count())));
  }
  if (m_options.referenceEvery > 0 && ++m_framesSinceKeyframe >= m_options.referenceEvery) {
    m_framesSinceKeyframe = 0;
    for (const auto& [id, peer] : m_peers) {
      if (peer->loadedVertexCount > 0 && !peer->connection->isClosing()) sendKeyframe(*peer->connection);
    }
  }
  emit frameSent(m_frame);
}

void SessionHost::produceStillFrame() {
  // A drag that came in meanwhile sends its own (moving) frame: no still frame then.
  if (m_shutDown || m_coalesce->isActive() || m_pendingArrival) return;
  ++m_counters.stillFramesSent;
  produceFrame();
}

void SessionHost::sendKeyframe(HostPeerConnection& connection) {
  Keyframe keyframe;
  keyframe.frame = m_frame;
  keyframe.z.resize(static_cast<std::size_t>(m_Z.rows()) * 3);
  for (Eigen::Index r = 0; r < m_Z.rows(); ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) keyframe.z[static_cast<std::size_t>(3 * r + c)] = m_Z(r, c);
  }
  connection.send(keyframe);
  ++m_counters.keyframesSent;
}

}  // namespace sc::session
