#include "app/gui/edit_actions.h"

#include <QAction>
#include <QKeySequence>

namespace sc::app {

EditActions::EditActions(QObject* parent) : QObject(parent) {
  m_undoAction = new QAction(tr("&Undo"), this);
  m_undoAction->setObjectName(QStringLiteral("actionUndo"));
  m_undoAction->setShortcut(QKeySequence::Undo);
  m_redoAction = new QAction(tr("&Redo"), this);
  m_redoAction->setObjectName(QStringLiteral("actionRedo"));
  m_redoAction->setShortcut(QKeySequence::Redo);
  connect(m_undoAction, &QAction::triggered, this, [this] { undo(); });
  connect(m_redoAction, &QAction::triggered, this, [this] { redo(); });
  refresh();
}

EditActions::~EditActions() = default;

void EditActions::bind(SessionController* session) {
  if (m_session != nullptr) m_session->disconnect(this);
  m_session = session;
  if (session != nullptr) {
    connect(session, &SessionController::editLogChanged, this, &EditActions::refresh);
    connect(session, &SessionController::stateChanged, this, &EditActions::refresh);
    connect(session, &SessionController::lockChanged, this, &EditActions::refresh);
  }
  refresh();
}

bool EditActions::allowed() const {
  return m_session != nullptr && m_session->state() == SessionController::State::Live && !m_session->dragging();
}

bool EditActions::canUndo() const { return allowed() && m_session->undoableStep().has_value(); }
bool EditActions::canRedo() const { return allowed() && m_session->redoableStep().has_value(); }

bool EditActions::undo() { return canUndo() && m_session->requestEdit(session::EditAction::Undo); }
bool EditActions::redo() { return canRedo() && m_session->requestEdit(session::EditAction::Redo); }

QString EditActions::stepText(const session::EditLogEntry& step) const {
  if (m_session != nullptr && step.author == m_session->selfId()) return tr("your drag");
  const QString name = step.authorName.isEmpty() ? tr("someone") : step.authorName;
  return step.author == session::kNoPeer ? tr("%1's saved drag").arg(name) : tr("%1's drag").arg(name);
}

void EditActions::refresh() {
  const std::optional<session::EditLogEntry> undoable = allowed() ? m_session->undoableStep() : std::nullopt;
  const std::optional<session::EditLogEntry> redoable = allowed() ? m_session->redoableStep() : std::nullopt;
  m_undoAction->setEnabled(undoable.has_value());
  m_redoAction->setEnabled(redoable.has_value());
  m_undoAction->setText(undoable ? tr("&Undo %1").arg(stepText(*undoable)) : tr("&Undo"));
  m_redoAction->setText(redoable ? tr("&Redo %1").arg(stepText(*redoable)) : tr("&Redo"));
  const bool host = m_session != nullptr && m_session->role() == SessionController::Role::Host;
  m_undoAction->setStatusTip(host ? tr("Undo the latest drag in this session, whoever made it (you host it)")
                                  : tr("Undo your latest drag; the others' drags stay"));
  m_redoAction->setStatusTip(tr("Redo the drag you undid last"));
}

}  // namespace sc::app
