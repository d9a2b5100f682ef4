// HostEngine: strokes and the session's shared edit history (issue 15, "edits that accumulate"). A stroke is what
// one person's poses did since the deformer's base; it ends at its author's StrokeEnd (the host's user: endStroke),
// at a new constraint set, or when its author's tenure of the lock ends, and becomes an EditStep. Undo / redo
// subtract / add a step's ΔZ and move the deformer's base with the shape, so a drag going on carries on from there.

#include "session/engine/host_engine.h"

namespace sc::session {

QString HostEngine::authorName(PeerId peer) const {
  if (peer == kHostPeer) return m_options.hostName;
  const auto it = m_peers.find(peer);
  return it != m_peers.end() ? it->second.name : QStringLiteral("peer %1").arg(peer);
}

void HostEngine::historyChanged(HostActions& out) {
  out.add(SendToAll{m_history.log()});
  out.add(EditHistoryChanged{});
}

void HostEngine::commitStroke(Micros now, HostActions& out) {
  if (m_pendingArrival && !m_constraintsInFlight) produceFrame(now, false, out);  // the stroke's last pose
  const PeerId author = m_strokeAuthor;
  m_strokeAuthor = kNoPeer;
  if (author == kNoPeer) return;
  const Eigen::MatrixXd& Z = *m_Z;
  if (!m_history.commit(author, authorName(author), Z - m_deformer->base())) return;
  m_deformer->rebase(Z);  // the next poses start from here
  ++m_counters.strokesCommitted;
  historyChanged(out);
}

void HostEngine::applyEdit(PeerId requester, EditAction action, Micros now, HostActions& out) {
  if (m_shutDown) return;
  commitStroke(now, out);  // a stroke going on is a step of its own first
  const bool anyAuthor = requester == kHostPeer;
  const EditStep* step =
      action == EditAction::Undo ? m_history.undoable(requester, anyAuthor) : m_history.redoable(requester);
  if (step == nullptr) {
    ++m_counters.editsRefused;
    return;
  }
  const Eigen::MatrixXd Z =
      action == EditAction::Undo ? Eigen::MatrixXd(*m_Z - step->delta) : Eigen::MatrixXd(*m_Z + step->delta);
  // The base moves with the shape: a pose of the stroke going on now acts from here (its own change is kept).
  const Eigen::MatrixXd base = m_deformer->base() + (Z - *m_Z);
  if (!m_deformer->rebase(base)) {
    ++m_counters.editsRefused;
    return;
  }
  if (action == EditAction::Undo) {
    m_history.undo(requester, anyAuthor);
  } else {
    m_history.redo(requester);
  }
  m_Z = std::make_shared<const Eigen::MatrixXd>(Z);
  ++m_counters.editsApplied;
  m_pendingArrival.reset();  // a pose not yet solved would overwrite the edit: the author's next one follows
  m_coalesceDue.reset();
  produceFrame(now, false, out, true);
  historyChanged(out);
}

HostActions HostEngine::endStroke(Micros now, bool* accepted) {
  HostActions out;
  const bool ok = m_arbiter.acceptDrag(kHostPeer, m_localLock.heldEpoch(), toMillis(now)) == DragVerdict::Accepted;
  if (ok) commitStroke(now, out);
  if (accepted) *accepted = ok;
  return finish(std::move(out));
}

HostActions HostEngine::edit(EditAction action, Micros now, bool* applied) {
  HostActions out;
  const std::uint64_t before = m_counters.editsApplied;
  applyEdit(kHostPeer, action, now, out);
  if (applied) *applied = m_counters.editsApplied != before;
  return finish(std::move(out));
}

bool HostEngine::restoreEdits(const Eigen::MatrixXd& Z, const std::vector<EditStep>& steps) {
  const auto fits = [this](const Eigen::MatrixXd& M) {
    return M.rows() == m_model->rowCount() && M.cols() == 3 && M.allFinite();
  };
  for (const EditStep& step : steps) {
    if (!fits(step.delta)) return false;
  }
  if (!fits(Z) || !m_deformer->rebase(Z)) return false;
  m_Z = std::make_shared<const Eigen::MatrixXd>(Z);
  for (const EditStep& step : steps) m_history.restore(step.authorName, step.delta, step.undoneBy != kNoPeer);
  return true;
}

}  // namespace sc::session
