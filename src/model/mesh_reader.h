#pragma once
// Private to shapecast_model: the one place that drives OpenMesh's file readers (see loadMesh() for the public
// entry point). This header does not include OpenMesh.

#include "model/mesh_error.h"
#include "model/triangle_soup.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <variant>

namespace sc::model::detail {

/// The file formats loadMesh() reads.
enum class MeshFormat { Off, Obj, Ply, Stl };

/// The format named by the extension of `path` (case-insensitive: .off .obj .ply .stl), or nullopt.
std::optional<MeshFormat> formatFromExtension(const std::filesystem::path& path);

/// Reads `path` (an existing, non-empty regular file of `fileBytes` bytes) after the checks of reader_guards.h:
/// ASCII OFF with readAsciiOff() (off_reader.h: double coordinates, '#' comments), every other format with
/// OpenMesh's reader for `format`, through SoupImporter (float32 coordinates: OpenMesh's readers deliver floats). A
/// truncated or malformed file, a header whose counts the file does not hold, or a face index out of range gives a
/// ReadFailed error naming the file. OFF, PLY and binary STL are read from a stream that throws on its first failed
/// read, so the reader stops there instead of going on with stale values; OBJ is read by file name (its material files
/// resolve next to it). OpenMesh's log streams (omerr/omlog/omout) are muted while it reads; a few messages it writes
/// straight to std::cerr on malformed PLY files are not. OpenMesh's readers are process-wide singletons with per-read
/// state, so calls are serialised by a mutex: safe to call from any thread. Cost: O(file size); STL also keeps
/// OpenMesh's O(#V log #V) vertex map.
std::variant<TriangleSoup, MeshError> readTriangleSoup(const std::filesystem::path& path, MeshFormat format,
                                                       std::uintmax_t fileBytes);

}  // namespace sc::model::detail
