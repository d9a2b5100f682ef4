#pragma once
// The host user's constraint set in the app's terms (HostConstraints, typed full-resolution ids) and in the session
// file's (model::SavedConstraints, plain ints, sorted), both ways. Used by File → Save Session… (session_snapshot.h)
// and the host restoring a saved session. Cost: O(#ids log #ids).

#include "app/gui/session_settings.h"
#include "model/session_file.h"

namespace sc::app {

/// Sorted, unique ids (what the file requires); the handle's ids are taken out of the anchors.
[[nodiscard]] model::SavedConstraints toSavedConstraints(const HostConstraints& state);
[[nodiscard]] HostConstraints toHostConstraints(const model::SavedConstraints& state);

}  // namespace sc::app
