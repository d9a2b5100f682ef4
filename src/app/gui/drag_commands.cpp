#include "app/gui/drag_commands.h"

#include "app/gui/saved_deformation.h"
#include "model/session_file.h"

#include <QAction>
#include <QKeySequence>
#include <QUndoStack>

#include <utility>

namespace sc::app {

DragCommand::DragCommand(SessionController* session, HostDeformation before, HostDeformation after)
    : QUndoCommand(QObject::tr("Drag")), m_session(session), m_before(std::move(before)), m_after(std::move(after)) {}

void DragCommand::undo() {
  m_done = false;
  if (m_session != nullptr) m_session->restoreHostDeformation(m_before);
}

void DragCommand::redo() {
  if (m_done) return;  // pushed right after the drag: it already happened
  if (m_session != nullptr) m_session->restoreHostDeformation(m_after);
}

DragHistory::DragHistory(QObject* parent) : QObject(parent), m_stack(new QUndoStack(this)) {
  m_undoAction = new QAction(tr("&Undo"), this);
  m_undoAction->setObjectName(QStringLiteral("actionUndo"));
  m_undoAction->setShortcut(QKeySequence::Undo);
  m_undoAction->setStatusTip(tr("Undo your last drag (host, while you hold the lock)"));
  m_redoAction = new QAction(tr("&Redo"), this);
  m_redoAction->setObjectName(QStringLiteral("actionRedo"));
  m_redoAction->setShortcut(QKeySequence::Redo);
  m_redoAction->setStatusTip(tr("Redo the drag you undid (host, while you hold the lock)"));
  connect(m_undoAction, &QAction::triggered, this, [this] { undo(); });
  connect(m_redoAction, &QAction::triggered, this, [this] { redo(); });
  connect(m_stack, &QUndoStack::indexChanged, this, &DragHistory::updateActions);
  updateActions();
}

DragHistory::~DragHistory() = default;

void DragHistory::bind(SessionController* session) {
  if (m_session != nullptr) m_session->disconnect(this);
  m_session = session;
  m_before.reset();
  m_stack->clear();
  if (session != nullptr) {
    connect(session, &SessionController::lockChanged, this, &DragHistory::updateActions);
    connect(session, &SessionController::stateChanged, this, &DragHistory::updateActions);
    connect(session, &SessionController::savedSessionRestored, this, &DragHistory::restoreSaved);
  }
  updateActions();
}

void DragHistory::dragStarted() {
  m_before = m_session != nullptr ? m_session->hostDeformation() : std::nullopt;
  updateActions();
}

void DragHistory::dragFinished() {
  std::optional<HostDeformation> after = m_session != nullptr ? m_session->hostDeformation() : std::nullopt;
  if (m_before && after && *after != *m_before) {
    m_stack->push(new DragCommand(m_session, std::move(*m_before), std::move(*after)));
  }
  m_before.reset();
  updateActions();
}

void DragHistory::restoreSaved() {
  const model::SessionFile* saved = m_session != nullptr ? m_session->savedSession() : nullptr;
  if (saved == nullptr) return;
  m_before.reset();
  m_stack->clear();
  std::vector<DragCommand*> commands;
  commands.reserve(saved->history.size());
  for (const model::SavedDrag& drag : saved->history) {
    // detached while rebuilding: push()'s redo() and setIndex()'s undo()s only move the index
    auto* command = new DragCommand(nullptr, toHostDeformation(drag.before), toHostDeformation(drag.after));
    m_stack->push(command);
    commands.push_back(command);
  }
  m_stack->setIndex(saved->historyIndex);
  for (DragCommand* command : commands) command->attach(m_session);
  updateActions();
  emit restored();
}

bool DragHistory::allowed() const {
  return m_session != nullptr && m_session->role() == SessionController::Role::Host && m_session->canDrag() &&
         !m_session->dragging();
}

bool DragHistory::canUndo() const { return allowed() && m_stack->canUndo(); }
bool DragHistory::canRedo() const { return allowed() && m_stack->canRedo(); }

bool DragHistory::undo() {
  if (!canUndo()) return false;
  m_stack->undo();
  emit restored();
  return true;
}

bool DragHistory::redo() {
  if (!canRedo()) return false;
  m_stack->redo();
  emit restored();
  return true;
}

void DragHistory::updateActions() {
  m_undoAction->setEnabled(canUndo());
  m_redoAction->setEnabled(canRedo());
  m_undoAction->setText(m_stack->canUndo() ? tr("&Undo %1").arg(m_stack->undoText()) : tr("&Undo"));
  m_redoAction->setText(m_stack->canRedo() ? tr("&Redo %1").arg(m_stack->redoText()) : tr("&Redo"));
}

}  // namespace sc::app
