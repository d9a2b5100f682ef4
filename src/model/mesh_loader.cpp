#include "model/mesh_loader.h"

#include "model/mesh_reader.h"

#include <fstream>
#include <new>
#include <system_error>

namespace sc::model {
namespace {

std::string quoted(const std::filesystem::path& path) {
  std::string text(1, '\'');
  text.append(path.string()).push_back('\'');
  return text;
}

/// Checks that `path` is a non-empty regular file in a known format; on success sets format and size.
std::optional<MeshError> checkFile(const std::filesystem::path& path, detail::MeshFormat& format,
                                   std::uintmax_t& bytes) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    const bool missing = !error || error == std::errc::no_such_file_or_directory;
    return MeshError{MeshErrorKind::FileNotFound,
                     "cannot load " + quoted(path) + ": " + (missing ? "no such file" : error.message())};
  }
  if (std::filesystem::is_directory(status)) {
    return MeshError{MeshErrorKind::FileNotFound, "cannot load " + quoted(path) + ": it is a directory, not a file"};
  }
  if (!std::filesystem::is_regular_file(status)) {
    return MeshError{MeshErrorKind::FileNotFound, "cannot load " + quoted(path) + ": not a regular file"};
  }
  const auto known = detail::formatFromExtension(path);
  if (!known) {
    return MeshError{MeshErrorKind::UnknownFormat, "cannot load " + quoted(path) + ": unknown extension '" +
                                                       path.extension().string() + "' (expected .off .obj .ply .stl)"};
  }
  format = *known;
  bytes = std::filesystem::file_size(path, error);
  if (error) {
    return MeshError{MeshErrorKind::FileNotFound, "cannot load " + quoted(path) + ": " + error.message()};
  }
  if (!std::ifstream(path, std::ios::binary)) {
    return MeshError{MeshErrorKind::FileNotFound, "cannot load " + quoted(path) + ": the file cannot be opened"};
  }
  if (bytes == 0) return MeshError{MeshErrorKind::ReadFailed, "cannot read " + quoted(path) + ": the file is empty"};
  return std::nullopt;
}

/// Rejects a soup with non-finite coordinates (any vertex, referenced or not).
std::optional<MeshError> checkFinite(const std::filesystem::path& path, const Eigen::MatrixXd& V) {
  Eigen::Index bad = 0;
  Eigen::Index first = -1;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (V.row(v).allFinite()) continue;
    if (first < 0) first = v;
    ++bad;
  }
  if (bad == 0) return std::nullopt;
  return MeshError{MeshErrorKind::NonFiniteCoordinates, "cannot use " + quoted(path) + ": " + std::to_string(bad) +
                                                            (bad == 1 ? " vertex has" : " vertices have") +
                                                            " NaN or infinite coordinates (the first is vertex " +
                                                            std::to_string(first) + ", counting from 0)"};
}

MeshLoadResult loadChecked(const std::filesystem::path& path) {
  detail::MeshFormat format{};
  std::uintmax_t bytes = 0;
  if (auto error = checkFile(path, format, bytes)) return *error;
  auto read = detail::readTriangleSoup(path, format, bytes);
  if (auto* error = std::get_if<MeshError>(&read)) return std::move(*error);
  auto& soup = std::get<detail::TriangleSoup>(read);
  if (auto error = checkFinite(path, soup.V)) return *error;
  if (soup.F.rows() == 0) {
    return MeshError{MeshErrorKind::NoFaces, "cannot use " + quoted(path) + ": it has " +
                                                 std::to_string(soup.V.rows()) + " vertices but no faces"};
  }
  LoadedMesh mesh{std::move(soup.V), std::move(soup.F), {}};
  mesh.cleaning = cleanMesh(mesh.V, mesh.F);
  if (mesh.F.rows() == 0) {
    return MeshError{MeshErrorKind::NoFaces, "cannot use " + quoted(path) + ": all " +
                                                 std::to_string(soup.polygonCount) +
                                                 " faces are degenerate (repeated corner or zero area)"};
  }
  return mesh;
}

}  // namespace

MeshLoadResult loadMesh(const std::filesystem::path& path) {
  // Nothing may escape: the GUI calls this from the Qt event loop.
  try {
    return loadChecked(path);
  } catch (const std::bad_alloc&) {
    return MeshError{MeshErrorKind::ReadFailed, "cannot read " + quoted(path) + ": out of memory"};
  } catch (const std::exception& e) {
    return MeshError{MeshErrorKind::ReadFailed, "cannot read " + quoted(path) + ": " + e.what()};
  } catch (...) {
    return MeshError{MeshErrorKind::ReadFailed, "cannot read " + quoted(path) + ": unexpected error"};
  }
}

const char* toString(MeshErrorKind kind) {
  switch (kind) {
    case MeshErrorKind::FileNotFound:
      return "file not found";
    case MeshErrorKind::UnknownFormat:
      return "unknown format";
    case MeshErrorKind::ReadFailed:
      return "read failed";
    case MeshErrorKind::NoFaces:
      return "no faces";
    case MeshErrorKind::NonFiniteCoordinates:
      return "non-finite coordinates";
  }
  return "unknown error";
}

}  // namespace sc::model
