#pragma once
// Loading triangle meshes from disk (OFF, OBJ, PLY ascii/binary, STL) into the Eigen (V, F) form of
// src/spectral, cleaned and with a report of what cleaning changed.

#include "model/mesh_cleaning.h"
#include "model/mesh_error.h"

#include <Eigen/Core>

#include <filesystem>
#include <variant>

namespace sc::model {

/// A loaded, triangulated and cleaned mesh.
struct LoadedMesh {
  Eigen::MatrixXd V;         ///< #V by 3 positions (double).
  Eigen::MatrixXi F;         ///< #F by 3 indices into V, consistently as read (no re-orientation).
  MeshCleanReport cleaning;  ///< what cleaning did and found.
};

/// Either the mesh or the error.
using MeshLoadResult = std::variant<LoadedMesh, MeshError>;

/// Reads a mesh file with OpenMesh, triangulates polygons (fan), converts to (V, F) and cleans it with
/// cleanMesh(). Never throws on bad input and never crashes: every failure comes back as a MeshError whose
/// message names the file and the problem.
///
/// Faces are kept as a soup, so non-manifold and duplicate faces load (OpenMesh's halfedge mesh would reject
/// them); cleanMesh() then drops duplicates and counts the rest. Vertex and face order are those of the file (STL:
/// vertices in order of first appearance).
/// A file counts as truncated when a reader runs out of data, or when fewer vertices or faces than its header
/// declares were read; an ASCII STL must end with "endsolid".
/// Thread-safe: OpenMesh's readers are process-wide singletons, so loads are serialised internally.
/// @param[in] path  file whose extension (case-insensitive) selects the format.
/// \note OpenMesh reads every coordinate as float32, so V holds float precision.
/// \note OFF comments and counts on the "OFF" line are not supported (ReadFailed). A file cut inside the very
///       last number of its last face, or an OBJ cut at a line end, still reads as a (smaller) valid mesh.
/// Cost: O(file size + #F log #F).
MeshLoadResult loadMesh(const std::filesystem::path& path);

/// Short name of an error kind ("file not found", "unknown format", …).
const char* toString(MeshErrorKind kind);

}  // namespace sc::model
