#pragma once
// What File → Save Session… writes: a model::SessionFile assembled from a live HostController (mesh, m,
// deformation mode, the host user's current state, Z) and the window's DragHistory (the committed drags and how
// many are applied). Composition only: the format is model/session_file.h's, the state the controller's and the
// history's, the conversion of the states saved_deformation.h's.

#include "app/gui/saved_deformation.h"
#include "model/session_file.h"

#include <QString>

#include <optional>

namespace sc::app {

class DragHistory;
class HostController;

/// The session to save: `session` must be live (its level, m, mode, hostDeformation() and coefficients());
/// `history` may be nullptr (no history saved). nullopt with a readable *error otherwise. Cost: O(#V + #F + ids).
[[nodiscard]] std::optional<model::SessionFile> snapshotSession(const HostController& session,
                                                                const DragHistory* history, QString* error = nullptr);

/// snapshotSession() written to `path` with model::writeSessionFile() (QSaveFile: an existing file is replaced
/// only by a complete one). False with a readable *error on failure.
bool saveSession(const QString& path, const HostController& session, const DragHistory* history,
                 QString* error = nullptr);

}  // namespace sc::app
