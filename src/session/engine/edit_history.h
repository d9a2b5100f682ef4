#pragma once
// The session's shared edit history (issue 15, "edits that accumulate"): every committed stroke, by anyone, is one
// step holding its author and the change of the coefficients it made, ΔZ (m by 3). Undoing a step subtracts its ΔZ
// from the current coefficients and redoing adds it back, whatever happened since: in the linear deformation the
// shape is the sum of the steps' changes, so undoing one person's step keeps everybody else's (selective undo).
// In rigid mode the steps do not add exactly; undo then subtracts the change as it was made.
//
// Rules:
//   - a member undoes its own latest applied step; the host's own user (anyAuthor) the latest applied step of
//     anybody; nothing else is ever taken out of the shape;
//   - redo re-applies the step the requester undid last, until the requester commits a newer step (then its undone
//     steps stay undone, visible in the log, as after a new edit in any editor);
//   - at most `capacity` steps are kept: the oldest is forgotten (its effect stays in the shape, or out of it).
// Pure: no sockets, no clock. Cost: O(steps) per call, O(m) per step's ΔZ.

#include "session/wire/control_messages.h"

#include <Eigen/Core>
#include <QtCore/QString>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

namespace sc::session {

/// Steps a host keeps (each m by 3 doubles: 2.4 KB at m = 100).
inline constexpr std::size_t kMaxEditSteps = 256;

struct EditStep {
  std::uint32_t id = 0;     ///< ≥ 1, increasing
  PeerId author = kNoPeer;  ///< kNoPeer: not in this session (restored)
  QString authorName;
  Eigen::MatrixXd delta;      ///< ΔZ, m by 3
  PeerId undoneBy = kNoPeer;  ///< kNoPeer: applied
  bool redoable = false;      ///< undoneBy may still redo it
};

class EditHistory {
 public:
  explicit EditHistory(std::size_t capacity = kMaxEditSteps);

  /// Records a committed stroke of `author`; clears the author's redo (its undone steps stay undone). A zero
  /// `delta` records nothing (false).
  bool commit(PeerId author, const QString& authorName, Eigen::MatrixXd delta);
  /// Appends a step restored from a saved session (author kNoPeer), applied or undone as it was saved; an undone
  /// one counts as undone by the host's own user (kHostPeer), who may redo it.
  void restore(const QString& authorName, Eigen::MatrixXd delta, bool undone);

  /// The step an undo by `requester` takes out: its latest applied step, or with `anyAuthor` the latest applied
  /// step of anybody; nullptr when none.
  [[nodiscard]] const EditStep* undoable(PeerId requester, bool anyAuthor) const;
  /// The step a redo by `requester` puts back (the one it undid last and may still redo); nullptr when none.
  [[nodiscard]] const EditStep* redoable(PeerId requester) const;
  /// Marks undoable(requester, anyAuthor) undone by `requester`; returns it (the caller subtracts its delta), or
  /// nullptr when there is none.
  const EditStep* undo(PeerId requester, bool anyAuthor);
  /// Marks redoable(requester) applied; returns it (the caller adds its delta), or nullptr.
  const EditStep* redo(PeerId requester);

  [[nodiscard]] const std::deque<EditStep>& steps() const { return m_steps; }
  /// The latest kMaxEditLogSteps steps as the wire lists them.
  [[nodiscard]] EditLog log() const;

 private:
  void append(EditStep step);
  EditStep* find(std::uint32_t id);

  std::size_t m_capacity;
  std::deque<EditStep> m_steps;  ///< oldest first
  std::uint32_t m_nextId = 1;
  /// The order in which steps were undone (ids): redo takes the requester's latest that is still redoable.
  std::vector<std::uint32_t> m_undoOrder;
};

/// What a member reads from the host's EditLog: the step its undo would take out (its own latest applied one; with
/// `anyAuthor`, as the host's own user, anybody's), nullopt when none. Cost: O(steps).
[[nodiscard]] std::optional<EditLogEntry> undoableIn(const EditLog& log, PeerId self, bool anyAuthor);
/// The step a redo by `self` would put back: the latest listed one it undid and may still redo (the host redoes the
/// one undone last, the same one whenever undos walked backwards), nullopt when none. Cost: O(steps).
[[nodiscard]] std::optional<EditLogEntry> redoableIn(const EditLog& log, PeerId self);

}  // namespace sc::session
