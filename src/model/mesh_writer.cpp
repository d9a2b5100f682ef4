#include "model/mesh_writer.h"

#include "model/mesh_reader.h"

#include <Eigen/Geometry>

#include <array>
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <system_error>

namespace sc::model {
namespace {

std::string quoted(const std::filesystem::path& path) { return '\'' + path.string() + '\''; }

std::optional<MeshWriteError> checkMesh(const std::filesystem::path& path, const Eigen::MatrixXd& V,
                                        const Eigen::MatrixXi& F) {
  const auto invalid = [&path](const std::string& problem) {
    return MeshWriteError{MeshWriteErrorKind::InvalidMesh, "cannot write " + quoted(path) + ": " + problem};
  };
  if (V.cols() != 3) return invalid("V must have 3 columns");
  if (F.cols() != 3) return invalid("F must have 3 columns (triangles)");
  if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows()))
    return invalid("a face index is out of range (mesh has " + std::to_string(V.rows()) + " vertices)");
  return std::nullopt;
}

void writeOff(std::ostream& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  out << "OFF\n" << V.rows() << ' ' << F.rows() << " 0\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) out << V(i, 0) << ' ' << V(i, 1) << ' ' << V(i, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f) out << "3 " << F(f, 0) << ' ' << F(f, 1) << ' ' << F(f, 2) << '\n';
}

void writeObj(std::ostream& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  out << "# written by ShapeCast\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) out << "v " << V(i, 0) << ' ' << V(i, 1) << ' ' << V(i, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f)  // OBJ indices are 1-based
    out << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';
}

void writePly(std::ostream& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  out << "ply\nformat ascii 1.0\ncomment written by ShapeCast\n"
      << "element vertex " << V.rows() << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "element face " << F.rows() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) out << V(i, 0) << ' ' << V(i, 1) << ' ' << V(i, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f) out << "3 " << F(f, 0) << ' ' << F(f, 1) << ' ' << F(f, 2) << '\n';
}

/// Appends a little-endian float32 (STL's only number type besides the count).
void putFloat(std::ostream& out, double value) {
  static_assert(std::endian::native == std::endian::little, "binary STL writer assumes a little-endian host");
  const float f = static_cast<float>(value);
  std::array<char, sizeof(float)> bytes{};
  std::memcpy(bytes.data(), &f, sizeof f);
  out.write(bytes.data(), bytes.size());
}

/// Binary STL: 80-byte header (must not start with "solid", or readers take it for ASCII), uint32 facet count,
/// then per facet the unit normal, three corners and a zero attribute word.
void writeStl(std::ostream& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::array<char, 80> header{};
  constexpr char kTitle[] = "binary STL written by ShapeCast";
  std::memcpy(header.data(), kTitle, sizeof kTitle - 1);
  out.write(header.data(), header.size());
  const auto count = static_cast<std::uint32_t>(F.rows());
  std::array<char, 4> countBytes{};
  std::memcpy(countBytes.data(), &count, sizeof count);
  out.write(countBytes.data(), countBytes.size());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();  // zero-area face: NaN-free zero (Eigen)
    for (const Eigen::Vector3d& p : {n, a, b, c})
      for (int k = 0; k < 3; ++k) putFloat(out, p(k));
    out.write("\0\0", 2);
  }
}

}  // namespace

std::optional<MeshWriteError> writeMesh(const std::filesystem::path& path, const Eigen::MatrixXd& V,
                                        const Eigen::MatrixXi& F) {
  const std::optional<detail::MeshFormat> format = detail::formatFromExtension(path);
  if (!format)
    return MeshWriteError{MeshWriteErrorKind::UnknownFormat,
                          "cannot write " + quoted(path) + ": unknown format (use .off .obj .ply or .stl)"};
  if (auto error = checkMesh(path, V, F)) return error;

  // === write a sibling temporary file, then rename it over `path`: a failure leaves no partial file
  std::filesystem::path partial = path;
  partial += ".part";
  std::ofstream out(partial, std::ios::binary | std::ios::trunc);
  const std::error_code openError(errno, std::generic_category());
  if (!out)
    return MeshWriteError{MeshWriteErrorKind::WriteFailed, "cannot write " + quoted(path) + ": " + openError.message()};
  out.precision(std::numeric_limits<double>::max_digits10);
  switch (*format) {
    case detail::MeshFormat::Off:
      writeOff(out, V, F);
      break;
    case detail::MeshFormat::Obj:
      writeObj(out, V, F);
      break;
    case detail::MeshFormat::Ply:
      writePly(out, V, F);
      break;
    case detail::MeshFormat::Stl:
      writeStl(out, V, F);
      break;
  }
  out.close();
  std::error_code error;
  if (out) std::filesystem::rename(partial, path, error);
  if (!out || error) {
    const std::string problem = out ? "cannot replace the file: " + error.message() : std::string("write failed");
    std::filesystem::remove(partial, error);
    return MeshWriteError{MeshWriteErrorKind::WriteFailed, "cannot write " + quoted(path) + ": " + problem};
  }
  return std::nullopt;
}

const char* toString(MeshWriteErrorKind kind) {
  switch (kind) {
    case MeshWriteErrorKind::UnknownFormat:
      return "unknown format";
    case MeshWriteErrorKind::InvalidMesh:
      return "invalid mesh";
    case MeshWriteErrorKind::WriteFailed:
      return "write failed";
  }
  return "unknown error";
}

}  // namespace sc::model
