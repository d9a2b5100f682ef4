#pragma once
// Test helpers for the model suite: a scratch folder and hand-written mesh files (independent of OpenMesh, so
// the loader is checked against a second implementation of each format).

#include <Eigen/Core>

#include <filesystem>
#include <ostream>
#include <string>
#include <string_view>

namespace sc::testing {

/// A fresh, empty folder under the system temp folder, removed with its contents on destruction.
class TempFolder {
 public:
  TempFolder();
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  /// Path of `name` inside the folder (nothing is created).
  std::filesystem::path file(std::string_view name) const { return m_path / name; }

 private:
  std::filesystem::path m_path;
};

/// Writes `bytes` to `path` verbatim (binary mode), replacing any file there.
void writeFile(const std::filesystem::path& path, std::string_view bytes);

/// Reads the whole file at `path`.
std::string readFile(const std::filesystem::path& path);

/// Keeps the first `keep` bytes of the file at `path`.
void truncateFile(const std::filesystem::path& path, std::size_t keep);

/// The encodings the writers below produce.
enum class FileFormat { Off, Obj, PlyAscii, PlyBinary, StlAscii, StlBinary };

/// Lower-case extension with the dot (".off", ".obj", ".ply" or ".stl").
const char* extensionOf(FileFormat format);

/// Name usable in a test name ("OFF", "PlyBinary", …).
const char* nameOf(FileFormat format);

/// Prints a format by name in GoogleTest's output.
inline void PrintTo(FileFormat format, std::ostream* out) { *out << nameOf(format); }

/// The file bytes of triangle mesh (V #V×3, F #F×3) in `format`. Text formats print 17 significant digits; PLY
/// binary is little-endian float32 with `list uchar int` faces; STL repeats each triangle's corners (no shared
/// vertices) with a zero normal.
std::string meshBytes(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FileFormat format);

}  // namespace sc::testing
