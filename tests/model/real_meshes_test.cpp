// loadMesh() on the real meshes fetched by scripts/fetch-meshes.sh into SHAPECAST_ASSETS_DIR (skipped when absent).

#include "model/mesh_loader.h"

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace sc::model {
namespace {

/// The face count a real mesh's header declares (OFF: second line; PLY: "element face N"), or -1.
long long declaredFaceCount(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  if (path.extension() == ".off") {
    long long vertices = 0, faces = -1;
    std::getline(in, line);
    in >> vertices >> faces;
    return faces;
  }
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string element, name;
    long long count = -1;
    if (words >> element >> name >> count && element == "element" && name == "face") return count;
  }
  return -1;
}

std::string describe(const MeshCleanReport& r) {
  std::ostringstream out;
  out << "merged " << r.mergedDuplicateVertices << ", repeated-index " << r.droppedRepeatedIndexFaces << ", zero-area "
      << r.droppedZeroAreaFaces << ", duplicate faces " << r.droppedDuplicateFaces << ", unreferenced "
      << r.droppedUnreferencedVertices << " | non-manifold edges " << r.nonManifoldEdges << ", boundary loops "
      << r.boundaryLoops << ", components " << r.components;
  return out.str();
}

struct RealMeshCase {
  const char* file;
  bool scanDefects;  ///< the Stanford vrip dragons: non-manifold edges and duplicate faces
};

void PrintTo(const RealMeshCase& c, std::ostream* out) { *out << c.file; }

class RealMesh : public ::testing::TestWithParam<RealMeshCase> {};

TEST_P(RealMesh, LoadsFullyFiniteAndClean) {
  const std::filesystem::path path = std::filesystem::path(SHAPECAST_ASSETS_DIR) / GetParam().file;
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << path << " is absent: run scripts/fetch-meshes.sh to fetch the real meshes";
  }
  const MeshLoadResult result = loadMesh(path);
  const auto* error = std::get_if<MeshError>(&result);
  ASSERT_EQ(error, nullptr) << toString(error->kind) << ": " << error->message;
  const LoadedMesh& mesh = std::get<LoadedMesh>(result);
  const MeshCleanReport& report = mesh.cleaning;
  std::cout << "[ report   ] " << GetParam().file << ": #V " << mesh.V.rows() << ", #F " << mesh.F.rows() << " | "
            << describe(report) << '\n';
  RecordProperty("cleaning", describe(report));

  EXPECT_TRUE(mesh.V.allFinite());
  ASSERT_GT(mesh.F.rows(), 0);
  ASSERT_GE(mesh.F.minCoeff(), 0);
  ASSERT_LT(mesh.F.maxCoeff(), mesh.V.rows());
  Eigen::VectorXi uses = Eigen::VectorXi::Zero(mesh.V.rows());
  for (Eigen::Index i = 0; i < mesh.F.size(); ++i) ++uses(mesh.F(i));
  EXPECT_GT(uses.minCoeff(), 0) << "every vertex must be referenced after cleaning";

  // Loaded fully: every triangle of the file is either kept or accounted for by a cleaning count.
  const long long declared = declaredFaceCount(path);
  ASSERT_GT(declared, 0);
  EXPECT_EQ(
      mesh.F.rows() + report.droppedRepeatedIndexFaces + report.droppedZeroAreaFaces + report.droppedDuplicateFaces,
      declared);
  EXPECT_GE(report.components, 1);
  // Plausibility: cleaning may repair a scan, not gut it.
  EXPECT_GT(mesh.F.rows(), declared * 9 / 10);
  if (GetParam().scanDefects) {
    // The dragons must load in full although OpenMesh's halfedge mesh would reject these faces.
    EXPECT_GT(report.nonManifoldEdges, 0);
    EXPECT_GT(report.droppedDuplicateFaces, 0);
  } else {
    EXPECT_EQ(report.nonManifoldEdges, 0);
    EXPECT_EQ(report.droppedDuplicateFaces, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Assets, RealMesh,
                         ::testing::Values(RealMeshCase{"lion.off", false}, RealMeshCase{"elephant.off", false},
                                           RealMeshCase{"ChineseDragon-10kv.off", false},
                                           RealMeshCase{"dragon_vrip_res4.ply", true},
                                           RealMeshCase{"dragon_vrip_res3.ply", true},
                                           RealMeshCase{"dragon_vrip_res2.ply", true}),
                         [](const auto& test) {
                           std::string name = test.param.file;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace sc::model
