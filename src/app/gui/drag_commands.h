#pragma once
// Undo/redo of committed drags on the host (issue 5 item 10). A committed drag is what happens between the
// viewport's dragStarted and dragFinished: the host's deformer goes from one HostDeformation (constraints + pose)
// to another. A DragCommand stores both and replays either through SessionController::restoreHostDeformation(),
// i.e. through SessionHost's local-user API (setConstraints + drag): the host solves that pose again and sends
// the resulting Z, so undo and redo change the shape for everyone.
//
// Scope (deliberate): only the host's own drags are recorded, and only the host's user, while holding the lock,
// can undo or redo (the actions are disabled otherwise). A client's drags are not recorded; undoing on the host
// after a client dragged restores the host's recorded state, replacing the client's constraints and pose. Each
// command restores an absolute state, so the history stays meaningful whatever happened in between.
//
// A host started from a saved session (model/session_file.h) gets the saved history back: on the controller's
// savedSessionRestored() the stack is rebuilt from the file's drags with the file's index, so Undo/Redo walk the
// same states as before saving.

#include "app/gui/session_controller.h"

#include <QObject>
#include <QPointer>
#include <QUndoCommand>

#include <optional>

class QAction;
class QUndoStack;

namespace sc::app {

/// One committed drag of the host's user: redo() restores `after`, undo() restores `before`. The first redo()
/// (QUndoStack::push) does nothing: the drag already happened. A restore that the session refuses (lock lost,
/// session gone) leaves the shape as it is.
class DragCommand final : public QUndoCommand {
 public:
  DragCommand(SessionController* session, HostDeformation before, HostDeformation after);

  void undo() override;
  void redo() override;

  [[nodiscard]] const HostDeformation& before() const { return m_before; }
  [[nodiscard]] const HostDeformation& after() const { return m_after; }
  /// The session undo()/redo() restore through (nullptr: they only move the stack's index, as while rebuilding
  /// a saved history).
  void attach(SessionController* session) { m_session = session; }

 private:
  QPointer<SessionController> m_session;
  HostDeformation m_before;
  HostDeformation m_after;
  bool m_done = true;  ///< the drag itself was the first redo
};

/// The host's drag history: a QUndoStack of DragCommands plus Undo/Redo actions (objectNames "actionUndo" and
/// "actionRedo", standard shortcuts) that are enabled only while the bound session is a live host whose user
/// holds the lock and is not dragging. The window calls dragStarted()/dragFinished() around a drag that the
/// session accepted (after SessionController::beginDrag() succeeded / after endDrag()).
class DragHistory final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(DragHistory)

 public:
  explicit DragHistory(QObject* parent = nullptr);
  ~DragHistory() override;

  /// Follows `session` (may be nullptr) from now on; clears the history.
  void bind(SessionController* session);
  /// Records the state before a drag (no-op unless hosting).
  void dragStarted();
  /// Pushes a DragCommand when the drag changed the state since dragStarted().
  void dragFinished();
  /// Replaces the history with the bound session's savedSession() drags, `historyIndex` of them applied, without
  /// changing the shape (the controller restored the file's current state). Emits restored(). No-op without a
  /// saved session. Cost: O(drags · ids).
  void restoreSaved();

  /// Undoes / redoes one drag; false when not allowed now (see canUndo()) or nothing to undo / redo.
  bool undo();
  bool redo();
  [[nodiscard]] bool canUndo() const;
  [[nodiscard]] bool canRedo() const;

  [[nodiscard]] QUndoStack* stack() const { return m_stack; }
  [[nodiscard]] QAction* undoAction() const { return m_undoAction; }
  [[nodiscard]] QAction* redoAction() const { return m_redoAction; }

 signals:
  /// Undo or redo restored a state: the session's handle() and anchors() may have changed (re-show them).
  void restored();

 private:
  [[nodiscard]] bool allowed() const;
  void updateActions();

  QPointer<SessionController> m_session;
  QUndoStack* m_stack = nullptr;
  QAction* m_undoAction = nullptr;
  QAction* m_redoAction = nullptr;
  std::optional<HostDeformation> m_before;
};

}  // namespace sc::app
