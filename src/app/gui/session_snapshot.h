#pragma once
// What File → Save Session… writes: a model::SessionFile assembled from a live host's SessionController (mesh, m,
// deformation mode, the host user's current state, Z) and the window's DragHistory (the committed drags and how
// many are applied), plus the conversions between the app's HostDeformation and the file's SavedDeformation.
// Composition only: the format is model/session_file.h's, the state the controller's and the history's.

#include "app/gui/session_controller.h"
#include "model/session_file.h"

#include <QString>

#include <optional>

namespace sc::app {

class DragHistory;

/// The same state in the file's terms (and back). Cost: O(#ids).
[[nodiscard]] model::SavedDeformation toSavedDeformation(const HostDeformation& state);
[[nodiscard]] HostDeformation toHostDeformation(const model::SavedDeformation& state);

/// The session to save: `session` must be a live host (its model, m, mode, hostDeformation() and coefficients());
/// `history` may be nullptr (no history saved). nullopt with a readable *error otherwise. Cost: O(#V + #F + ids).
[[nodiscard]] std::optional<model::SessionFile> snapshotSession(const SessionController& session,
                                                                const DragHistory* history, QString* error = nullptr);

/// snapshotSession() written to `path` with model::writeSessionFile() (QSaveFile: an existing file is replaced
/// only by a complete one). False with a readable *error on failure.
bool saveSession(const QString& path, const SessionController& session, const DragHistory* history,
                 QString* error = nullptr);

}  // namespace sc::app
