#include "mesh_files.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace sc::testing {
namespace {

static_assert(std::endian::native == std::endian::little, "the binary writers assume a little-endian host");

template <typename T>
void appendRaw(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

std::ostringstream preciseStream() {
  std::ostringstream out;
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  return out;
}

std::string offText(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  auto out = preciseStream();
  out << "OFF\n" << V.rows() << ' ' << F.rows() << " 0\n";
  for (Eigen::Index v = 0; v < V.rows(); ++v) out << V(v, 0) << ' ' << V(v, 1) << ' ' << V(v, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f) out << "3 " << F(f, 0) << ' ' << F(f, 1) << ' ' << F(f, 2) << '\n';
  return out.str();
}

std::string objText(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  auto out = preciseStream();
  out << "# written by the ShapeCast model tests\n";
  for (Eigen::Index v = 0; v < V.rows(); ++v) out << "v " << V(v, 0) << ' ' << V(v, 1) << ' ' << V(v, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    out << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';  // OBJ counts from 1
  }
  return out.str();
}

std::string plyHeader(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const char* encoding) {
  std::ostringstream out;
  out << "ply\nformat " << encoding << " 1.0\nelement vertex " << V.rows()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << F.rows()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  return out.str();
}

std::string plyAscii(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  auto out = preciseStream();
  out << plyHeader(V, F, "ascii");
  for (Eigen::Index v = 0; v < V.rows(); ++v) out << V(v, 0) << ' ' << V(v, 1) << ' ' << V(v, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f) out << "3 " << F(f, 0) << ' ' << F(f, 1) << ' ' << F(f, 2) << '\n';
  return out.str();
}

std::string plyBinary(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::string out = plyHeader(V, F, "binary_little_endian");
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    for (int k = 0; k < 3; ++k) appendRaw(out, static_cast<float>(V(v, k)));
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    appendRaw(out, std::uint8_t{3});
    for (int k = 0; k < 3; ++k) appendRaw(out, static_cast<std::int32_t>(F(f, k)));
  }
  return out;
}

std::string stlAscii(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  auto out = preciseStream();
  out << "solid shapecast\n";
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const Eigen::Index v = F(f, k);
      out << "      vertex " << V(v, 0) << ' ' << V(v, 1) << ' ' << V(v, 2) << '\n';
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid shapecast\n";
  return out.str();
}

std::string stlBinary(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::string out(80, ' ');
  out.replace(0, 20, "ShapeCast model test");  // must not start with "solid"
  appendRaw(out, static_cast<std::uint32_t>(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) appendRaw(out, 0.0f);  // normal
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) appendRaw(out, static_cast<float>(V(F(f, c), k)));
    }
    appendRaw(out, std::uint16_t{0});
  }
  return out;
}

}  // namespace

TempFolder::TempFolder() {
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    m_path = std::filesystem::temp_directory_path() / ("shapecast-model-test-" + std::to_string(entropy()));
    if (std::filesystem::create_directory(m_path)) return;
  }
  throw std::runtime_error("cannot create a temporary folder");
}

TempFolder::~TempFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(m_path, ignored);
}

void writeFile(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void truncateFile(const std::filesystem::path& path, std::size_t keep) { std::filesystem::resize_file(path, keep); }

const char* extensionOf(FileFormat format) {
  switch (format) {
    case FileFormat::Off:
      return ".off";
    case FileFormat::Obj:
      return ".obj";
    case FileFormat::PlyAscii:
    case FileFormat::PlyBinary:
      return ".ply";
    case FileFormat::StlAscii:
    case FileFormat::StlBinary:
      return ".stl";
  }
  return "";
}

const char* nameOf(FileFormat format) {
  switch (format) {
    case FileFormat::Off:
      return "OFF";
    case FileFormat::Obj:
      return "OBJ";
    case FileFormat::PlyAscii:
      return "PlyAscii";
    case FileFormat::PlyBinary:
      return "PlyBinary";
    case FileFormat::StlAscii:
      return "StlAscii";
    case FileFormat::StlBinary:
      return "StlBinary";
  }
  return "";
}

std::string meshBytes(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FileFormat format) {
  switch (format) {
    case FileFormat::Off:
      return offText(V, F);
    case FileFormat::Obj:
      return objText(V, F);
    case FileFormat::PlyAscii:
      return plyAscii(V, F);
    case FileFormat::PlyBinary:
      return plyBinary(V, F);
    case FileFormat::StlAscii:
      return stlAscii(V, F);
    case FileFormat::StlBinary:
      return stlBinary(V, F);
  }
  return "";
}

}  // namespace sc::testing
