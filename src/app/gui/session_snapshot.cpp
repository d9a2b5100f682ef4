#include "app/gui/session_snapshot.h"

#include "app/gui/host_controller.h"
#include "session/engine/edit_history.h"

#include <QCoreApplication>

#include <algorithm>

namespace sc::app {
namespace {

/// `name` cut to at most `maxBytes` of UTF-8 (whole characters).
QString clipped(QString name, int maxBytes) {
  while (name.toUtf8().size() > maxBytes) name.chop(name.back().isLowSurrogate() ? 2 : 1);
  return name;
}

}  // namespace

std::optional<model::SessionFile> snapshotSession(const HostController& session, QString* error) {
  if (session.state() != SessionController::State::Live || !session.displayLevel()) {
    if (error != nullptr)
      *error = QCoreApplication::translate("SessionSnapshot", "Only a live host can save its session.");
    return std::nullopt;
  }
  model::SessionFile file;
  file.V = session.displayRestPositions();
  file.F = session.displayFaces();
  file.Z = session.coefficients();
  file.m = static_cast<int>(file.Z.rows());
  file.mode = session.deformationMode();
  if (const std::optional<HostConstraints> current = session.sentConstraints(); current && !current->handle.empty()) {
    file.current = toSavedConstraints(*current);
  }
  const std::vector<session::EditStep> steps = session.editSteps();
  const std::size_t first = steps.size() > static_cast<std::size_t>(model::kMaxSavedEditSteps)
                                ? steps.size() - static_cast<std::size_t>(model::kMaxSavedEditSteps)
                                : 0;
  for (std::size_t i = first; i < steps.size(); ++i) {
    file.steps.push_back({clipped(steps[i].authorName, model::kMaxStepAuthorBytes), steps[i].delta,
                          steps[i].undoneBy != session::kNoPeer});
  }
  return file;
}

bool saveSession(const QString& path, const HostController& session, QString* error) {
  const std::optional<model::SessionFile> file = snapshotSession(session, error);
  if (!file) return false;
  if (const std::optional<QString> failure = model::writeSessionFile(path, *file)) {
    if (error != nullptr) *error = *failure;
    return false;
  }
  return true;
}

}  // namespace sc::app
