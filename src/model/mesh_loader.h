#pragma once
// Loading triangle meshes from disk (OFF, OBJ, PLY ascii/binary, STL) into the Eigen (V, F) form of
// src/spectral, cleaned and with a report of what cleaning changed.

#include "model/mesh_cleaning.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <variant>

namespace sc::model {

/// Why a mesh could not be loaded.
enum class MeshErrorKind {
  FileNotFound,          ///< no such file, or it is not a regular readable file.
  UnknownFormat,         ///< the extension is none of .off .obj .ply .stl.
  ReadFailed,            ///< the reader rejected the file: truncated, malformed header, bad index, …
  NoFaces,               ///< nothing triangulable is left (after cleaning).
  NonFiniteCoordinates,  ///< a vertex coordinate is NaN or ±∞.
};

/// A typed load error with a message that names the file and the problem.
struct MeshError {
  MeshErrorKind kind{};
  std::string message;
};

/// A loaded, triangulated and cleaned mesh.
struct LoadedMesh {
  Eigen::MatrixXd V;         ///< #V by 3 positions (double).
  Eigen::MatrixXi F;         ///< #F by 3 indices into V, consistently as read (no re-orientation).
  MeshCleanReport cleaning;  ///< what cleaning did and found.
};

/// Either the mesh or the error.
using MeshLoadResult = std::variant<LoadedMesh, MeshError>;

/// Reads a mesh file with OpenMesh, triangulates polygons (fan), converts to (V, F) and cleans it with
/// cleanMesh(). Never throws on bad input and never crashes: every failure comes back as a MeshError.
/// @param[in] path  file whose extension (case-insensitive) selects the format.
/// Cost: O(file size + #F log #F).
MeshLoadResult loadMesh(const std::filesystem::path& path);

/// Short name of an error kind ("file not found", "unknown format", …).
const char* toString(MeshErrorKind kind);

}  // namespace sc::model
