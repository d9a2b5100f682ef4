// HostEngine: moderation by the host's user (kick a member, take the lock back) and the lock queue's announcement
// (LockNotice{Waiting}: who waits for the lock, so that its holder sees it).

#include "session/engine/host_engine.h"

namespace sc::session {

HostActions HostEngine::kick(PeerId id, Micros now, const QString& text, bool* kicked) {
  HostActions out;
  Peer* peer = id == kHostPeer ? nullptr : welcomed(id);
  const bool member = peer != nullptr && !peer->closing && !m_shutDown;
  if (kicked) *kicked = member;
  if (!member) return finish(std::move(out));
  out.add(SendToPeer{id, Leave{LeaveReason::Kicked, text}});
  closePeer(*peer, ClosePeer::How::Graceful, out);  // onClosed() forgets it; its lock goes now
  dispatchLock(m_arbiter.peerDisconnected(id, toMillis(now)), now, out);
  out.add(SendToAll{peerList()});  // without the closing peer
  out.add(LogLine{QStringLiteral("peer %1 (%2) removed by the host").arg(id).arg(peer->name)});
  out.add(PeersChanged{});
  return finish(std::move(out));
}

HostActions HostEngine::forceReleaseLock(Micros now, bool* revoked, PeerId holder) {
  HostActions out;
  const bool holds = holder == kNoPeer ? m_arbiter.holder() != kNoPeer : m_arbiter.epochOf(holder) != kNoEpoch;
  if (revoked) *revoked = holds && !m_shutDown;
  if (!holds || m_shutDown) return finish(std::move(out));
  const LockEvents events = m_arbiter.revokeByHost(toMillis(now), holder);
  for (const LockEvent& event : events) {
    if (event.notice.kind == LockNoticeKind::Released) {
      out.add(LogLine{QStringLiteral("the host took the lock back from peer %1").arg(event.notice.peer)});
    }
  }
  dispatchLock(events, now, out);
  return finish(std::move(out));
}

LockNotice HostEngine::waitingNotice() const {
  LockNotice notice{LockNoticeKind::Waiting, kNoPeer, kNoEpoch, 0, LockReleaseReason::Released, {}};
  notice.waiting.assign(m_arbiter.queue().begin(), m_arbiter.queue().end());  // ≤ maxPeers + 1 ≤ kMaxPeers
  return notice;
}

bool HostEngine::announceLockQueue(Micros now, HostActions& out) {
  if (m_arbiter.queue() == m_announcedQueue) return false;
  m_announcedQueue = m_arbiter.queue();
  const LockNotice notice = waitingNotice();
  out.add(SendToAll{notice});
  m_localLock.apply(notice, toMillis(now));  // a Waiting notice never asks for a reply
  return true;
}

}  // namespace sc::session
