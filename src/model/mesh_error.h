#pragma once
// The typed error of mesh loading, shared by the public loader (mesh_loader.h) and the file readers behind it
// (mesh_reader.h), so that neither header needs the other.

#include <string>

namespace sc::model {

/// Why a mesh could not be loaded.
enum class MeshErrorKind {
  FileNotFound,          ///< no such file, or it is not a regular readable file (a directory, no permission).
  UnknownFormat,         ///< the extension is none of .off .obj .ply .stl.
  ReadFailed,            ///< the reader rejected the file: empty, truncated, malformed header, bad index, …
  NoFaces,               ///< nothing triangulable is left (after cleaning).
  NonFiniteCoordinates,  ///< a vertex coordinate is NaN or ±∞ (only binary PLY/STL can hold such values).
};

/// A typed load error with a message that names the file and the problem.
struct MeshError {
  MeshErrorKind kind{};
  std::string message;
};

}  // namespace sc::model
