#pragma once
// Where per-user caches (harmonic bases) live.

#include <filesystem>

namespace sc::model {

/// The per-user folder for cached manifold harmonic bases: $XDG_CACHE_HOME/shapecast/bases (typically
/// ~/.cache/shapecast/bases), from QStandardPaths::GenericCacheLocation. The folder may not exist yet.
std::filesystem::path basisCacheDirectory();

}  // namespace sc::model
