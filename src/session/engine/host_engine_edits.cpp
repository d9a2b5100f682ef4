// HostEngine: strokes and the session's shared edit history (issue 15, "edits that accumulate" and "several people
// drag at once"). A stroke is what one holder's poses did; several go on at once, each moving its own groups of the
// union. At every move of the deformer's base (a stroke's end, a new union, undo / redo) each stroke's share of the
// change is set aside and its poses folded in, so that it carries on from the new base with relative poses.
// A stroke ends at its author's StrokeEnd (the host's user: endStroke), at its author's new constraint set, or when
// its author's lease ends, and becomes an EditStep. Undo / redo subtract / add a step's ΔZ and move the base with
// the shape, so the drags going on carry on from there.

#include "session/engine/host_engine.h"

#include <algorithm>

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

namespace {

/// `pose` after `folded` is already in the base: the pose that moves the group from there, R·R_fᵀ and t − t_f
/// (the group's base centroid moved by t_f; exact when the group followed its folded pose, which the soft
/// constraints make nearly so).
spectral::HandleTransform relativeTo(const spectral::HandleTransform& pose, const spectral::HandleTransform& folded) {
  spectral::HandleTransform out;
  out.rotation = pose.rotation * folded.rotation.transpose();
  out.translation = pose.translation - folded.translation;
  return out;
}

bool identity(std::span<const spectral::HandleTransform> poses) {
  return std::all_of(poses.begin(), poses.end(), [](const spectral::HandleTransform& T) {
    return T.translation.isZero(0.0) && T.rotation.isIdentity(0.0);
  });
}

}  // namespace

std::vector<spectral::HandleTransform> HostEngine::combinedPoses() {
  std::vector<std::vector<spectral::HandleTransform>> relative;  // kept alive for the spans below
  relative.reserve(m_strokes.size());
  return m_installed.layout([this, &relative](PeerId peer) -> std::span<const spectral::HandleTransform> {
    const auto it = m_strokes.find(peer);
    if (it == m_strokes.end()) return {};
    Stroke& stroke = it->second;
    stroke.solved = stroke.received;
    stroke.unsolved = false;
    std::vector<spectral::HandleTransform>& poses = relative.emplace_back(stroke.received);
    for (std::size_t g = 0; g < poses.size() && g < stroke.folded.size(); ++g) {
      poses[g] = relativeTo(poses[g], stroke.folded[g]);
    }
    return poses;
  });
}

void HostEngine::foldStrokes(Micros now, HostActions& out) {
  if (m_pendingArrival && !m_constraintsInFlight) produceFrame(now, false, out);  // the strokes' last poses
  // Each stroke's share of Z − base: the change of its own relative poses alone (exact in linear mode, where the
  // shares add up to the whole); the last stroke that moved takes what is left, so that the shares always add up.
  std::vector<std::pair<Stroke*, std::vector<spectral::HandleTransform>>> moving;
  for (auto& [peer, stroke] : m_strokes) {
    const std::optional<GroupRange> range = m_installed.groups(peer);
    if (!range || stroke.solved.empty()) continue;
    std::vector<spectral::HandleTransform> alone(range->first + range->count);
    for (std::size_t g = 0; g < range->count && g < stroke.solved.size(); ++g) {
      alone[range->first + g] =
          g < stroke.folded.size() ? relativeTo(stroke.solved[g], stroke.folded[g]) : stroke.solved[g];
    }
    if (!identity(alone)) moving.emplace_back(&stroke, std::move(alone));
  }
  Eigen::MatrixXd left = *m_Z - m_deformer->base();
  for (std::size_t i = 0; i < moving.size(); ++i) {
    Stroke& stroke = *moving[i].first;
    const Eigen::MatrixXd share = i + 1 == moving.size() ? left : m_deformer->change(moving[i].second);
    left -= share;
    stroke.share = stroke.share.size() == 0 ? share : Eigen::MatrixXd(stroke.share + share);
  }
  for (auto& [peer, stroke] : m_strokes) {
    if (!stroke.solved.empty()) stroke.folded = stroke.solved;
  }
}

void HostEngine::commitStroke(Micros now, HostActions& out, PeerId author) {
  foldStrokes(now, out);
  m_deformer->rebase(*m_Z);  // every stroke goes on from here (its poses relative to what was folded)
  bool changed = false;
  for (auto it = m_strokes.begin(); it != m_strokes.end();) {
    if (author != kNoPeer && it->first != author) {
      ++it;
      continue;
    }
    Stroke& stroke = it->second;
    if (stroke.share.size() != 0 && m_history.commit(it->first, authorName(it->first), stroke.share)) {
      ++m_counters.strokesCommitted;
      changed = true;
    }
    stroke.share.resize(0, 0);
    if (author != kNoPeer) {
      it = m_strokes.erase(it);  // its author's next poses start a new stroke from identity
    } else {
      ++it;  // a drag going on carries on (its poses stay relative to what is folded), its next share a new step
    }
  }
  if (changed) historyChanged(out);
}

void HostEngine::endStrokeOf(PeerId author, Micros now, HostActions& out) {
  const auto it = m_strokes.find(author);
  if (m_constraintsInFlight && it != m_strokes.end() && it->second.unsolved) {
    it->second.ending = true;  // onConstraintsPrepared() solves its last poses, then commits
    return;
  }
  commitStroke(now, out, author);
}

void HostEngine::endEditing(PeerId peer, Micros now, HostActions& out) {
  if (m_arbiter.epochOf(peer) != kNoEpoch) return;  // granted again at once: its set goes on
  if (m_strokes.contains(peer)) commitStroke(now, out, peer);
  if (m_shared.remove(peer) && !m_shutDown) prepareUnion(out);
}

void HostEngine::applyEdit(PeerId requester, EditAction action, Micros now, HostActions& out) {
  if (m_shutDown) return;
  commitStroke(now, out);  // every stroke going on is a step of its own first
  const bool anyAuthor = requester == kHostPeer;
  const EditStep* step =
      action == EditAction::Undo ? m_history.undoable(requester, anyAuthor) : m_history.redoable(requester);
  if (step == nullptr) {
    ++m_counters.editsRefused;
    return;
  }
  const Eigen::MatrixXd Z =
      action == EditAction::Undo ? Eigen::MatrixXd(*m_Z - step->delta) : Eigen::MatrixXd(*m_Z + step->delta);
  // The strokes going on were folded into the base: their next poses act from the new shape.
  if (!m_deformer->rebase(Z)) {
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
  if (ok) endStrokeOf(kHostPeer, now, out);
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
