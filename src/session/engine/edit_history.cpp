#include "session/engine/edit_history.h"

#include <algorithm>
#include <utility>

namespace sc::session {

EditHistory::EditHistory(std::size_t capacity) : m_capacity(std::max<std::size_t>(capacity, 1)) {}

void EditHistory::append(EditStep step) {
  step.id = m_nextId++;
  m_steps.push_back(std::move(step));
  while (m_steps.size() > m_capacity) {
    std::erase(m_undoOrder, m_steps.front().id);
    m_steps.pop_front();
  }
}

EditStep* EditHistory::find(std::uint32_t id) {
  const auto it = std::find_if(m_steps.begin(), m_steps.end(), [id](const EditStep& s) { return s.id == id; });
  return it == m_steps.end() ? nullptr : &*it;
}

bool EditHistory::commit(PeerId author, const QString& authorName, Eigen::MatrixXd delta) {
  if (delta.size() == 0 || delta.isZero(0.0)) return false;
  for (EditStep& step : m_steps) {
    if (step.undoneBy == author) step.redoable = false;
  }
  std::erase_if(m_undoOrder, [this](std::uint32_t id) {
    const EditStep* step = find(id);
    return step == nullptr || !step->redoable;
  });
  append({0, author, authorName, std::move(delta), kNoPeer, false});
  return true;
}

void EditHistory::restore(const QString& authorName, Eigen::MatrixXd delta, bool undone) {
  // A saved session's undone steps were undone by its host: the host's own user may redo them, as before saving.
  append({0, kNoPeer, authorName, std::move(delta), undone ? kHostPeer : kNoPeer, undone});
  if (undone) m_undoOrder.push_back(m_steps.back().id);
}

const EditStep* EditHistory::undoable(PeerId requester, bool anyAuthor) const {
  const auto it = std::find_if(m_steps.rbegin(), m_steps.rend(), [&](const EditStep& s) {
    return s.undoneBy == kNoPeer && (anyAuthor || s.author == requester);
  });
  return it == m_steps.rend() ? nullptr : &*it;
}

const EditStep* EditHistory::redoable(PeerId requester) const {
  for (auto it = m_undoOrder.rbegin(); it != m_undoOrder.rend(); ++it) {
    const auto step =
        std::find_if(m_steps.begin(), m_steps.end(), [id = *it](const EditStep& s) { return s.id == id; });
    if (step != m_steps.end() && step->undoneBy == requester && step->redoable) return &*step;
  }
  return nullptr;
}

const EditStep* EditHistory::undo(PeerId requester, bool anyAuthor) {
  const EditStep* candidate = undoable(requester, anyAuthor);
  if (candidate == nullptr) return nullptr;
  EditStep* step = find(candidate->id);
  step->undoneBy = requester;
  step->redoable = true;
  m_undoOrder.push_back(step->id);
  return step;
}

const EditStep* EditHistory::redo(PeerId requester) {
  const EditStep* candidate = redoable(requester);
  if (candidate == nullptr) return nullptr;
  EditStep* step = find(candidate->id);
  step->undoneBy = kNoPeer;
  step->redoable = false;
  std::erase(m_undoOrder, step->id);
  return step;
}

EditLog EditHistory::log() const {
  EditLog out;
  const std::size_t first = m_steps.size() > kMaxEditLogSteps ? m_steps.size() - kMaxEditLogSteps : 0;
  for (std::size_t i = first; i < m_steps.size(); ++i) {
    const EditStep& s = m_steps[i];
    QString name = s.authorName;
    while (name.toUtf8().size() > kMaxNameBytes) name.chop(name.back().isLowSurrogate() ? 2 : 1);  // whole characters
    out.steps.push_back({s.id, s.author, s.undoneBy, s.redoable, name});
  }
  return out;
}

std::optional<EditLogEntry> undoableIn(const EditLog& log, PeerId self, bool anyAuthor) {
  for (auto it = log.steps.rbegin(); it != log.steps.rend(); ++it) {
    if (it->undoneBy == kNoPeer && (anyAuthor || it->author == self)) return *it;
  }
  return std::nullopt;
}

std::optional<EditLogEntry> redoableIn(const EditLog& log, PeerId self) {
  for (auto it = log.steps.rbegin(); it != log.steps.rend(); ++it) {
    if (it->undoneBy == self && it->redoable) return *it;
  }
  return std::nullopt;
}

}  // namespace sc::session
