#include "app/gui/session_snapshot.h"

#include "app/gui/drag_commands.h"
#include "app/gui/host_controller.h"

#include <QCoreApplication>
#include <QUndoStack>

namespace sc::app {

std::optional<model::SessionFile> snapshotSession(const HostController& session, const DragHistory* history,
                                                  QString* error) {
  const auto fail = [error](const char* why) {
    if (error != nullptr) *error = QCoreApplication::translate("SessionSnapshot", why);
    return std::nullopt;
  };
  if (session.state() != SessionController::State::Live || !session.displayLevel()) {
    return fail("Only a live host can save its session.");
  }
  model::SessionFile file;
  file.V = session.displayRestPositions();
  file.F = session.displayFaces();
  file.Z = session.coefficients();
  file.m = static_cast<int>(file.Z.rows());
  file.mode = session.deformationMode();
  if (const std::optional<HostDeformation> current = session.hostDeformation()) {
    file.current = toSavedDeformation(*current);
  }
  if (history != nullptr) {
    const QUndoStack* stack = history->stack();
    for (int i = 0; i < stack->count(); ++i) {
      const auto* drag = dynamic_cast<const DragCommand*>(stack->command(i));
      if (drag == nullptr) return fail("The undo history holds something other than drags.");
      file.history.push_back({toSavedDeformation(drag->before()), toSavedDeformation(drag->after())});
    }
    file.historyIndex = stack->index();
  }
  return file;
}

bool saveSession(const QString& path, const HostController& session, const DragHistory* history, QString* error) {
  const std::optional<model::SessionFile> file = snapshotSession(session, history, error);
  if (!file) return false;
  if (const std::optional<QString> failure = model::writeSessionFile(path, *file)) {
    if (error != nullptr) *error = *failure;
    return false;
  }
  return true;
}

}  // namespace sc::app
