// loadMesh(): round trips through every format, polygon triangulation, and every kind of bad input.

#include "model/mesh_loader.h"
#include "mesh_files.h"
#include "spectral/laplace_operators.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace sc::model {
namespace {

using sc::testing::FileFormat;
using sc::testing::GeneratedMesh;
using sc::testing::TempFolder;

std::string describe(const MeshLoadResult& result) {
  if (const auto* error = std::get_if<MeshError>(&result)) {
    return std::string(toString(error->kind)) + ": " + error->message;
  }
  return "loaded";
}

/// Base fixture: a scratch folder and helpers that write a file and load it.
class MeshLoaderTest : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, std::string_view bytes) const {
    const auto path = m_folder.file(name);
    sc::testing::writeFile(path, bytes);
    return path;
  }
  /// Loads `path` and expects an error of `kind` whose message names the file.
  static MeshError expectError(const std::filesystem::path& path, MeshErrorKind kind) {
    const MeshLoadResult result = loadMesh(path);
    const auto* error = std::get_if<MeshError>(&result);
    if (error == nullptr) {
      ADD_FAILURE() << path << " loaded, but " << toString(kind) << " was expected";
      return {};
    }
    EXPECT_EQ(error->kind, kind) << error->message;
    EXPECT_NE(error->message.find(path.filename().string()), std::string::npos)
        << "the message must name the file: " << error->message;
    return *error;
  }

  TempFolder m_folder;
};

// === round trips: generated meshes written by hand in each format and read back

struct RoundTripCase {
  const char* name;
  GeneratedMesh mesh;
  int components;
  int boundaryLoops;
};

std::vector<RoundTripCase> roundTripCases() {
  return {{"icosphere", sc::testing::icosphere(2), 1, 0},
          {"torus", sc::testing::torus(16, 8), 1, 0},
          {"grid", sc::testing::grid(5, 3), 1, 1},
          {"twoSpheres", sc::testing::twoSpheres(1), 2, 0}};
}

class MeshRoundTrip : public MeshLoaderTest, public ::testing::WithParamInterface<FileFormat> {};

TEST_P(MeshRoundTrip, ReadsBackWhatWasWritten) {
  const FileFormat format = GetParam();
  const bool isStl = format == FileFormat::StlAscii || format == FileFormat::StlBinary;
  for (const RoundTripCase& c : roundTripCases()) {
    SCOPED_TRACE(c.name);
    const auto path = write(std::string(c.name) + sc::testing::extensionOf(format),
                            sc::testing::meshBytes(c.mesh.V, c.mesh.F, format));
    const MeshLoadResult result = loadMesh(path);
    const auto* mesh = std::get_if<LoadedMesh>(&result);
    ASSERT_NE(mesh, nullptr) << describe(result);

    // STL stores every triangle's corners separately: merging must restore the shared vertices.
    EXPECT_EQ(mesh->V.rows(), c.mesh.V.rows());
    ASSERT_EQ(mesh->F.rows(), c.mesh.F.rows());
    if (!isStl) {
      EXPECT_EQ(mesh->F, c.mesh.F) << "vertex and face order must be kept";
    }
    double worst = 0;  // corner by corner, whatever the vertex order; files hold float32 or parse to float
    for (Eigen::Index f = 0; f < c.mesh.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, (mesh->V.row(mesh->F(f, k)) - c.mesh.V.row(c.mesh.F(f, k))).norm());
      }
    }
    EXPECT_LT(worst, 1e-6);

    const MeshCleanReport& report = mesh->cleaning;
    EXPECT_EQ(report.mergedDuplicateVertices, 0) << "OpenMesh's STL reader merges exact duplicates itself";
    EXPECT_EQ(report.droppedRepeatedIndexFaces + report.droppedZeroAreaFaces + report.droppedDuplicateFaces, 0);
    EXPECT_EQ(report.droppedUnreferencedVertices, 0);
    EXPECT_EQ(report.nonManifoldEdges, 0);
    EXPECT_EQ(report.boundaryLoops, c.boundaryLoops);
    EXPECT_EQ(report.components, c.components);
  }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, MeshRoundTrip,
                         ::testing::Values(FileFormat::Off, FileFormat::Obj, FileFormat::PlyAscii,
                                           FileFormat::PlyBinary, FileFormat::StlAscii, FileFormat::StlBinary),
                         [](const auto& test) { return std::string(sc::testing::nameOf(test.param)); });

TEST_F(MeshLoaderTest, ExtensionIsCaseInsensitive) {
  const GeneratedMesh ico = sc::testing::icosphere(1);
  const auto path = write("UPPER.OFF", sc::testing::meshBytes(ico.V, ico.F, FileFormat::Off));
  EXPECT_TRUE(std::holds_alternative<LoadedMesh>(loadMesh(path))) << describe(loadMesh(path));
}

TEST_F(MeshLoaderTest, WindowsLineEndingsLoad) {
  const GeneratedMesh ico = sc::testing::icosphere(1);
  for (const FileFormat format : {FileFormat::Off, FileFormat::Obj, FileFormat::PlyAscii, FileFormat::StlAscii}) {
    SCOPED_TRACE(sc::testing::nameOf(format));
    std::string crlf;
    for (const char c : sc::testing::meshBytes(ico.V, ico.F, format))
      crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const MeshLoadResult result = loadMesh(write(std::string("crlf") + sc::testing::extensionOf(format), crlf));
    const auto* mesh = std::get_if<LoadedMesh>(&result);
    ASSERT_NE(mesh, nullptr) << describe(result);
    EXPECT_EQ(mesh->V.rows(), ico.V.rows());
    EXPECT_EQ(mesh->F.rows(), ico.F.rows());
  }
}

// === polygons are fan-triangulated around their first corner

/// Square 0-1-2-3 (z = 0) and pentagon 4…8 (z = 1), as polygons:
///
///   3-----2          7
///   |     |       8     6        fans: (0 1 2) (0 2 3)
///   |     |        \   /               (4 5 6) (4 6 7) (4 7 8)
///   0-----1         4-5
const char* const kPolygonCorners =
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    "0 0 1\n1 0 1\n1.3 0.9 1\n0.5 1.5 1\n-0.3 0.9 1\n";

void expectFans(const MeshLoadResult& result) {
  const auto* mesh = std::get_if<LoadedMesh>(&result);
  ASSERT_NE(mesh, nullptr) << describe(result);
  Eigen::MatrixXi expected(5, 3);
  expected << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8;
  EXPECT_EQ(mesh->F, expected);
  EXPECT_EQ(mesh->cleaning.components, 2);
  EXPECT_EQ(mesh->cleaning.boundaryLoops, 2);
}

TEST_F(MeshLoaderTest, TriangulatesOffPolygons) {
  expectFans(
      loadMesh(write("polygons.off", std::string("OFF\n9 2 0\n") + kPolygonCorners + "4 0 1 2 3\n5 4 5 6 7 8\n")));
}

TEST_F(MeshLoaderTest, TriangulatesPlyPolygons) {
  expectFans(loadMesh(write("polygons.ply", std::string("ply\nformat ascii 1.0\nelement vertex 9\n"
                                                        "property float x\nproperty float y\nproperty float z\n"
                                                        "element face 2\nproperty list uchar int vertex_indices\n"
                                                        "end_header\n") +
                                                kPolygonCorners + "4 0 1 2 3\n5 4 5 6 7 8\n")));
}

TEST_F(MeshLoaderTest, TriangulatesObjPolygonsWithAttributesAndNegativeIndices) {
  std::string obj;
  std::istringstream corners(kPolygonCorners);
  for (std::string line; std::getline(corners, line);) obj += "v " + line + "\n";
  obj += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";
  obj += "f 1/1/1 2/2/1 3/3/1 4/4/1\n";        // v/vt/vn
  obj += "f -5//1 -4//1 -3//1 -2//1 -1//1\n";  // negative indices count back from the last vertex
  expectFans(loadMesh(write("polygons.obj", obj)));
}

// === bad input: a typed error naming the file, never a crash or an exception

constexpr int kCorruptionTrials = 200;

TEST_F(MeshLoaderTest, MissingFileIsFileNotFound) {
  expectError(m_folder.file("absent.off"), MeshErrorKind::FileNotFound);
}

TEST_F(MeshLoaderTest, DirectoryIsFileNotFound) {
  const auto path = m_folder.file("folder.off");
  std::filesystem::create_directory(path);
  EXPECT_NE(expectError(path, MeshErrorKind::FileNotFound).message.find("directory"), std::string::npos);
}

TEST_F(MeshLoaderTest, UnknownExtensionIsUnknownFormat) {
  expectError(write("points.xyz", "0 0 0\n"), MeshErrorKind::UnknownFormat);
  expectError(write("no_extension", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), MeshErrorKind::UnknownFormat);
}

TEST_F(MeshLoaderTest, EmptyFileIsReadFailed) {
  for (const char* name : {"empty.off", "empty.obj", "empty.ply", "empty.stl"}) {
    SCOPED_TRACE(name);
    expectError(write(name, ""), MeshErrorKind::ReadFailed);
  }
}

TEST_F(MeshLoaderTest, MalformedHeadersAreReadFailed) {
  expectError(write("hello.off", "HELLO\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), MeshErrorKind::ReadFailed);
  expectError(write("garbage.ply", "ply\nformat fancy 9.9\nend_header\n"), MeshErrorKind::ReadFailed);
  // OpenMesh's own PLY header parser would loop forever on these (the guard rejects them first).
  for (const char* header :
       {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", "ply\nformat ascii 1.0\ncomment no end in sight",
        "ply\nformat ascii 1.0\nelement vertex many\nend_header\n", "ply\nformat ascii x\nend_header\n"}) {
    expectError(write("endless.ply", header), MeshErrorKind::ReadFailed);
  }
  expectError(write("orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n"), MeshErrorKind::ReadFailed);
  expectError(write("garbage.stl", "neither solid nor binary"), MeshErrorKind::ReadFailed);
  expectError(write("sameline.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), MeshErrorKind::ReadFailed);
  // A NaN or infinite coordinate is refused, not read.
  expectError(write("inf.off", "OFF\n3 1 0\ninf 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), MeshErrorKind::ReadFailed);
  expectError(write("nan.off", "OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, OffWithCommentsLoads) {
  // Comments on their own lines, after values, and blank lines; colours after the coordinates are ignored.
  const MeshLoadResult result = loadMesh(write("comment.off",
                                               "OFF\n# made by hand\n\n3 1 0  # counts\n0 0 0 # origin\n"
                                               "1 0 0 255 0 0\n  0 1 0\n# the face\n3 0 1 2\n"));
  ASSERT_TRUE(std::holds_alternative<LoadedMesh>(result)) << describe(result);
  const LoadedMesh& mesh = std::get<LoadedMesh>(result);
  EXPECT_EQ(mesh.V.rows(), 3);
  ASSERT_EQ(mesh.F.rows(), 1);
  EXPECT_EQ(mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.V.row(1), Eigen::RowVector3d(1, 0, 0));
}

TEST_F(MeshLoaderTest, OffFaceDeclaringMoreCornersThanItHoldsIsReadFailed) {
  // The corner count is not trusted: corners are read from the line one by one, nothing is reserved for 4e9 of them.
  const char* const corners = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
  const MeshError error =
      expectError(write("corners.off", std::string(corners) + "4000000000 0 1 2\n"), MeshErrorKind::ReadFailed);
  EXPECT_NE(error.message.find("holds fewer indices"), std::string::npos) << error.message;
  expectError(write("word.off", std::string(corners) + "3 0 one 2\n"), MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, OffCoordinatesKeepDoublePrecisionThroughCleaningAndTheOperators) {
  // A 3 × 3 grid 2e-9 apart at x ≈ 1, z = 1 + 1e-9: float32 would round every x to 1 and z to 1 (the columns would
  // merge and every face would collapse). Written with 17 significant digits, read back bit for bit.
  constexpr double h = 2e-9;
  std::ostringstream off;
  off.precision(17);
  off << "OFF\n9 8 0\n";
  Eigen::MatrixXd written(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      written.row(3 * j + i) << 1.0 + i * h, j * h, 1.0 + 1e-9;
      off << written(3 * j + i, 0) << ' ' << written(3 * j + i, 1) << ' ' << written(3 * j + i, 2) << '\n';
    }
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      off << "3 " << a << ' ' << a + 1 << ' ' << a + 4 << "\n3 " << a << ' ' << a + 4 << ' ' << a + 3 << '\n';
    }
  const MeshLoadResult result = loadMesh(write("fine.off", off.str()));
  ASSERT_TRUE(std::holds_alternative<LoadedMesh>(result)) << describe(result);
  const LoadedMesh& mesh = std::get<LoadedMesh>(result);
  EXPECT_EQ(mesh.cleaning.mergedDuplicateVertices, 0);
  EXPECT_EQ(mesh.cleaning.droppedZeroAreaFaces, 0);
  ASSERT_EQ(mesh.F.rows(), 8);
  EXPECT_EQ(mesh.V, written) << "every coordinate as written";
  EXPECT_NE(static_cast<double>(static_cast<float>(mesh.V(0, 2))), mesh.V(0, 2)) << "float32 would round it";
  // The operators the basis is computed from see the true geometry: area (2h)², no mollification needed.
  const spectral::LaplaceOperators ops = spectral::laplaceOperators(mesh.V, mesh.F);
  EXPECT_NEAR(ops.totalArea, 4 * h * h, 1e-6 * 4 * h * h);
  EXPECT_EQ(ops.mollifyEpsilon, 0.0);
}

/// Writes the icosphere in `format`, cuts the file to `fraction` of its size and expects ReadFailed.
class TruncatedFile : public MeshLoaderTest, public ::testing::WithParamInterface<std::tuple<FileFormat, double>> {};

TEST_P(TruncatedFile, IsReadFailed) {
  const auto [format, fraction] = GetParam();
  const GeneratedMesh ico = sc::testing::icosphere(2);
  const std::string bytes = sc::testing::meshBytes(ico.V, ico.F, format);
  const auto path = write(std::string("cut") + sc::testing::extensionOf(format), bytes);
  sc::testing::truncateFile(path, static_cast<std::size_t>(fraction * static_cast<double>(bytes.size())));
  expectError(path, MeshErrorKind::ReadFailed);
}

// 0.2 cuts into the vertices, 0.5 and 0.97 into the faces (OBJ is left out: a cut OBJ is still a valid OBJ).
INSTANTIATE_TEST_SUITE_P(CutFiles, TruncatedFile,
                         ::testing::Combine(::testing::Values(FileFormat::Off, FileFormat::PlyAscii,
                                                              FileFormat::PlyBinary, FileFormat::StlAscii,
                                                              FileFormat::StlBinary),
                                            ::testing::Values(0.2, 0.5, 0.97)),
                         [](const auto& test) {
                           return std::string(sc::testing::nameOf(std::get<0>(test.param))) + "_" +
                                  std::to_string(static_cast<int>(100 * std::get<1>(test.param))) + "percent";
                         });

TEST_F(MeshLoaderTest, OffWithFewerVertexLinesThanItsHeaderIsReadFailed) {
  expectError(write("short.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, OffMissingItsLastFaceIsReadFailed) {
  // Without the stream check OpenMesh would repeat the previous face's indices for the missing one.
  expectError(write("lastface.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n"), MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, HeaderCountsBeyondTheFileSizeAreReadFailed) {
  const MeshError error = expectError(write("liar.off", "OFF\n4000000000 1 0\n0 0 0\n"), MeshErrorKind::ReadFailed);
  EXPECT_NE(error.message.find("header declares"), std::string::npos) << error.message;
}

TEST_F(MeshLoaderTest, OutOfRangeFaceIndexIsReadFailed) {
  const char* const corners = "0 0 0\n1 0 0\n0 1 0\n";
  const MeshError error =
      expectError(write("range.off", std::string("OFF\n3 1 0\n") + corners + "3 0 1 7\n"), MeshErrorKind::ReadFailed);
  EXPECT_NE(error.message.find("vertex index 7"), std::string::npos) << error.message;
  expectError(write("negative.off", std::string("OFF\n3 1 0\n") + corners + "3 0 -1 2\n"), MeshErrorKind::ReadFailed);
  expectError(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), MeshErrorKind::ReadFailed);
  expectError(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), MeshErrorKind::ReadFailed);
  expectError(write("range.ply",
                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
              MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, ObjCornerWithoutVertexIndexIsReadFailed) {
  // OpenMesh's OBJ reader would fail an assertion here and abort the whole process.
  expectError(write("slash.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf /1 2 3\n"), MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, ObjMaterialLibraryThatIsNotAFileIsReadFailed) {
  // OpenMesh would read a material "file" such as /dev/zero forever; a missing one is only skipped.
  std::filesystem::create_directory(m_folder.file("folder.mtl"));
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  expectError(write("material.obj", "mtllib folder.mtl\n" + triangle), MeshErrorKind::ReadFailed);
  write("real.mtl", "newmtl red\nKd 1 0 0\n");
  for (const char* library : {"mtllib absent.mtl\n", "mtllib real.mtl\nusemtl red\n"}) {
    const MeshLoadResult result = loadMesh(write("material.obj", library + triangle));
    EXPECT_TRUE(std::holds_alternative<LoadedMesh>(result)) << describe(result);
  }
}

TEST_F(MeshLoaderTest, FaceWithTwoCornersIsReadFailed) {
  expectError(write("edge.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), MeshErrorKind::ReadFailed);
}

TEST_F(MeshLoaderTest, NoFacesIsNoFaces) {
  expectError(write("points.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), MeshErrorKind::NoFaces);
  expectError(write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), MeshErrorKind::NoFaces);
  // Every face is dropped by cleaning: a repeated corner, and three collinear corners.
  const MeshError error = expectError(write("degenerate.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0 1\n3 0 1 2\n"),
                                      MeshErrorKind::NoFaces);
  EXPECT_NE(error.message.find("degenerate"), std::string::npos) << error.message;
}

TEST_F(MeshLoaderTest, NonFiniteCoordinatesAreRejected) {
  GeneratedMesh ico = sc::testing::icosphere(1);
  ico.V(5, 1) = std::numeric_limits<double>::quiet_NaN();
  expectError(write("nan.ply", sc::testing::meshBytes(ico.V, ico.F, FileFormat::PlyBinary)),
              MeshErrorKind::NonFiniteCoordinates);
  ico.V(5, 1) = std::numeric_limits<double>::infinity();
  expectError(write("inf.stl", sc::testing::meshBytes(ico.V, ico.F, FileFormat::StlBinary)),
              MeshErrorKind::NonFiniteCoordinates);
  // OBJ text cannot hold a non-finite number OpenMesh reads: the line is unreadable instead.
  const MeshError error =
      expectError(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 4\n"), MeshErrorKind::ReadFailed);
  EXPECT_NE(error.message.find("'v' lines"), std::string::npos) << error.message;
}

TEST_F(MeshLoaderTest, RandomBytesNeverThrow) {
  std::mt19937 random(12345);
  for (const char* extension : {".off", ".obj", ".ply", ".stl"}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::string bytes(static_cast<std::size_t>(random() % 2000), '\0');
      for (char& b : bytes) b = static_cast<char>(random() % 256);
      if (trial % 2 == 1) bytes.insert(0, std::string(extension + 1) == "ply" ? "ply\n" : "OFF\n");
      const auto path = write("random" + std::to_string(trial) + extension, bytes);
      EXPECT_NO_THROW(static_cast<void>(loadMesh(path))) << path;
    }
  }
}

TEST_F(MeshLoaderTest, CorruptedFilesNeverThrow) {
  // Valid files with a few bytes overwritten reach deeper into the readers than random bytes do.
  const GeneratedMesh ico = sc::testing::icosphere(1);
  std::mt19937 random(6789);
  for (const FileFormat format : {FileFormat::Off, FileFormat::Obj, FileFormat::PlyAscii, FileFormat::PlyBinary,
                                  FileFormat::StlAscii, FileFormat::StlBinary}) {
    const std::string original = sc::testing::meshBytes(ico.V, ico.F, format);
    for (int trial = 0; trial < kCorruptionTrials; ++trial) {
      std::string bytes = original;
      for (int hit = 0; hit < 4; ++hit) bytes[random() % bytes.size()] = static_cast<char>(random() % 256);
      const auto path = write(std::string("corrupt") + sc::testing::extensionOf(format), bytes);
      EXPECT_NO_THROW(static_cast<void>(loadMesh(path))) << sc::testing::nameOf(format) << " trial " << trial;
    }
  }
}

TEST(MeshErrorKind, HasDistinctNames) {
  const std::vector<MeshErrorKind> kinds = {MeshErrorKind::FileNotFound, MeshErrorKind::UnknownFormat,
                                            MeshErrorKind::ReadFailed, MeshErrorKind::NoFaces,
                                            MeshErrorKind::NonFiniteCoordinates};
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    for (std::size_t j = i + 1; j < kinds.size(); ++j) EXPECT_STRNE(toString(kinds[i]), toString(kinds[j]));
  }
}

}  // namespace
}  // namespace sc::model
