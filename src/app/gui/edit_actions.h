#pragma once
// Edit → Undo / Redo of the session's shared edit history (issue 15): every committed drag, by anyone, is a step
// with its author (session/engine/edit_history.h). Undo asks the host to take out this user's latest step (the
// host's own user: anybody's, it moderates); redo puts back the step this user undid last. The host applies either
// to the shape everybody sees, so nobody's work is dropped silently: undoing one person's step keeps the others'.
// Undo needs no lock (it is not a drag), only a live session and no drag of this user going on.
//
// The actions (objectNames "actionUndo" / "actionRedo", standard shortcuts) say whose step they would undo or redo
// ("Undo bob's drag"), and are enabled exactly when the session's editLog() has such a step.

#include "app/gui/session_controller.h"

#include <QObject>
#include <QPointer>

class QAction;

namespace sc::app {

class EditActions final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(EditActions)

 public:
  explicit EditActions(QObject* parent = nullptr);
  ~EditActions() override;

  /// Follows `session` (may be nullptr) from now on.
  void bind(SessionController* session);
  /// Re-reads whether undo / redo are possible (the window calls it around a drag).
  void refresh();

  /// Asks for an undo / a redo; false when not possible now.
  bool undo();
  bool redo();
  [[nodiscard]] bool canUndo() const;
  [[nodiscard]] bool canRedo() const;

  [[nodiscard]] QAction* undoAction() const { return m_undoAction; }
  [[nodiscard]] QAction* redoAction() const { return m_redoAction; }

 private:
  [[nodiscard]] bool allowed() const;
  [[nodiscard]] QString stepText(const session::EditLogEntry& step) const;

  QPointer<SessionController> m_session;
  QAction* m_undoAction = nullptr;
  QAction* m_redoAction = nullptr;
};

}  // namespace sc::app
