#pragma once
// The host user's deformer state in the app's terms (HostDeformation, typed full-resolution ids) and in the
// session file's (model::SavedDeformation, plain ints), both ways. Used by the undo history (drag_commands.h),
// File → Save Session… (session_snapshot.h) and the host restoring a saved session. Cost: O(#ids).

#include "app/gui/session_settings.h"
#include "model/session_file.h"

namespace sc::app {

[[nodiscard]] model::SavedDeformation toSavedDeformation(const HostDeformation& state);
[[nodiscard]] HostDeformation toHostDeformation(const model::SavedDeformation& state);

}  // namespace sc::app
