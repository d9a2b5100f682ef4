#pragma once
// Writing triangle meshes (V, F) to disk in the formats loadMesh() reads: OFF, OBJ, PLY (ASCII) and STL (binary).

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>

namespace sc::model {

/// Why a mesh could not be written.
enum class MeshWriteErrorKind {
  UnknownFormat,  ///< the extension is none of .off .obj .ply .stl.
  InvalidMesh,    ///< V is not #V by 3, F is not #F by 3, or a face index is out of range.
  WriteFailed,    ///< the file could not be created or a write failed (folder missing, no permission, disk full).
};

/// A typed write error with a message that names the file and the problem.
struct MeshWriteError {
  MeshWriteErrorKind kind{};
  std::string message;
};

/// Writes the triangle mesh (V, F) to `path`, in the format named by its extension (case-insensitive).
///
/// The faces are written as given, as a soup: non-manifold and duplicate faces are kept, unlike a write through
/// OpenMesh's halfedge TriMesh, which refuses them (the Stanford dragons have thousands). OFF, OBJ and PLY are
/// ASCII with 17 significant digits (doubles round-trip exactly); STL is binary (float32, per-face normals, the
/// vertices repeated per face, as the format requires). On failure no partial file is left behind.
/// @param[in] path  output file; an existing file is replaced.
/// @param[in] V  #V by 3 positions.
/// @param[in] F  #F by 3 vertex indices into V.
/// @return std::nullopt on success, else the error.
/// Cost: O(#V + #F).
std::optional<MeshWriteError> writeMesh(const std::filesystem::path& path, const Eigen::MatrixXd& V,
                                        const Eigen::MatrixXi& F);

/// Short name of an error kind ("unknown format", …).
const char* toString(MeshWriteErrorKind kind);

}  // namespace sc::model
