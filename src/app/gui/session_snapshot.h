#pragma once
// What File → Save Session… writes: a model::SessionFile assembled from a live HostController: mesh, m, deformation
// mode, the host user's current constraints, Z and the session's edit history (every step's author, ΔZ and
// whether it is undone). Composition only: the format is model/session_file.h's, the state the controller's, the
// conversion of the constraints saved_constraints.h's.

#include "app/gui/saved_constraints.h"
#include "model/session_file.h"

#include <QString>

#include <optional>

namespace sc::app {

class HostController;

/// The session to save: `session` must be live. The newest model::kMaxSavedEditSteps steps are kept (a host keeps
/// no more). nullopt with a readable *error otherwise. Cost: O(#V + #F + ids + steps · m).
[[nodiscard]] std::optional<model::SessionFile> snapshotSession(const HostController& session,
                                                                QString* error = nullptr);

/// snapshotSession() written to `path` with model::writeSessionFile() (QSaveFile: an existing file is replaced
/// only by a complete one). False with a readable *error on failure.
bool saveSession(const QString& path, const HostController& session, QString* error = nullptr);

}  // namespace sc::app
