// writeMesh(): round trips through loadMesh() in every format, soups that a halfedge mesh refuses, and errors.

#include "model/mesh_writer.h"

#include "model/mesh_loader.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <QTemporaryDir>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sc::model {
namespace {

using sc::testing::GeneratedMesh;

class MeshWriter : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override { ASSERT_TRUE(m_dir.isValid()); }
  std::filesystem::path file(const std::string& name) const {
    return std::filesystem::path(m_dir.path().toStdString()) / name;
  }
  static LoadedMesh writeAndLoad(const std::filesystem::path& path, const GeneratedMesh& mesh) {
    const auto error = writeMesh(path, mesh.V, mesh.F);
    EXPECT_FALSE(error) << error->message;
    MeshLoadResult loaded = loadMesh(path);
    if (const auto* loadError = std::get_if<MeshError>(&loaded)) {
      ADD_FAILURE() << loadError->message;
      return {};
    }
    return std::get<LoadedMesh>(std::move(loaded));
  }
  QTemporaryDir m_dir;
};

/// Every face of `a` has a face of `b` at the same index with the same corner positions (to float precision):
/// holds whatever vertex numbering the format imposes (STL repeats corners and is re-indexed on load).
void expectSameTriangles(const GeneratedMesh& a, const LoadedMesh& b) {
  ASSERT_EQ(a.F.rows(), b.F.rows());
  double worst = 0.0;
  for (Eigen::Index f = 0; f < a.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) worst = std::max(worst, (a.V.row(a.F(f, k)) - b.V.row(b.F(f, k))).norm());
  EXPECT_LT(worst, 1e-6) << "corner positions survive up to float32 rounding";
}

TEST_P(MeshWriter, RoundTripsThroughLoadMesh) {
  for (const GeneratedMesh& mesh : {sc::testing::torus(24, 10), sc::testing::twoSpheres(2)}) {
    const auto path = file(std::string("mesh") + GetParam());
    const LoadedMesh loaded = writeAndLoad(path, mesh);
    expectSameTriangles(mesh, loaded);
    EXPECT_EQ(loaded.V.rows(), mesh.V.rows()) << "shared vertices stay shared (STL: merged on load)";
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".part")) << "the temporary file is renamed away";
  }
}

TEST_P(MeshWriter, KeepsNonManifoldFaces) {
  // Three triangles on one edge (0,1): a fin that OpenMesh's TriMesh::add_face would refuse.
  GeneratedMesh fin;
  fin.V.resize(5, 3);
  fin.V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  fin.F.resize(3, 3);
  fin.F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const LoadedMesh loaded = writeAndLoad(file(std::string("fin") + GetParam()), fin);
  expectSameTriangles(fin, loaded);
  EXPECT_EQ(loaded.cleaning.nonManifoldEdges, 1);
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshWriter, ::testing::Values(".off", ".obj", ".ply", ".stl", ".OFF"));

TEST(MeshWriterText, OffKeepsDoublePrecisionDigits) {
  QTemporaryDir dir;
  const auto path = std::filesystem::path(dir.path().toStdString()) / "third.off";
  GeneratedMesh mesh = sc::testing::icosphere(0);
  mesh.V(0, 0) = 1.0 / 3.0;
  ASSERT_FALSE(writeMesh(path, mesh.V, mesh.F));
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("0.33333333333333331"), std::string::npos) << "17 significant digits";
}

TEST(MeshWriterErrors, NameTheFileAndTheProblem) {
  QTemporaryDir dir;
  const std::filesystem::path folder = dir.path().toStdString();
  const GeneratedMesh mesh = sc::testing::icosphere(1);

  const auto unknown = writeMesh(folder / "mesh.xyz", mesh.V, mesh.F);
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->kind, MeshWriteErrorKind::UnknownFormat);
  EXPECT_NE(unknown->message.find("mesh.xyz"), std::string::npos) << unknown->message;

  Eigen::MatrixXi badF = mesh.F;
  badF(3, 1) = static_cast<int>(mesh.V.rows());
  const auto invalid = writeMesh(folder / "bad.off", mesh.V, badF);
  ASSERT_TRUE(invalid);
  EXPECT_EQ(invalid->kind, MeshWriteErrorKind::InvalidMesh);
  EXPECT_FALSE(std::filesystem::exists(folder / "bad.off"));

  const auto missingFolder = writeMesh(folder / "no" / "such" / "folder.ply", mesh.V, mesh.F);
  ASSERT_TRUE(missingFolder);
  EXPECT_EQ(missingFolder->kind, MeshWriteErrorKind::WriteFailed);
  EXPECT_NE(missingFolder->message.find("folder.ply"), std::string::npos) << missingFolder->message;
  EXPECT_STREQ(toString(MeshWriteErrorKind::WriteFailed), "write failed");
}

TEST(MeshWriterErrors, ReplacesAnExistingFile) {
  QTemporaryDir dir;
  const auto path = std::filesystem::path(dir.path().toStdString()) / "twice.off";
  ASSERT_FALSE(writeMesh(path, sc::testing::icosphere(2).V, sc::testing::icosphere(2).F));
  const GeneratedMesh small = sc::testing::icosphere(0);
  ASSERT_FALSE(writeMesh(path, small.V, small.F));
  const MeshLoadResult loaded = loadMesh(path);
  ASSERT_TRUE(std::holds_alternative<LoadedMesh>(loaded));
  EXPECT_EQ(std::get<LoadedMesh>(loaded).V.rows(), 12);
}

}  // namespace
}  // namespace sc::model
