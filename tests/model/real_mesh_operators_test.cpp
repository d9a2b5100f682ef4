// The cotangent operators' invariants on every real mesh (loaded and cleaned by loadMesh), complementing the
// generated meshes of tests/spectral: S·1 = 0, S = Sᵀ, M > 0, everything finite.

#include "model/mesh_loader.h"
#include "spectral/laplace_operators.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace sc::model {
namespace {

class RealMeshOperators : public ::testing::TestWithParam<const char*> {};

TEST_P(RealMeshOperators, SatisfyTheLaplacianInvariants) {
  const std::filesystem::path path = std::filesystem::path(SHAPECAST_ASSETS_DIR) / GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not fetched (run scripts/fetch-meshes.sh)";
  const MeshLoadResult loaded = loadMesh(path);
  ASSERT_TRUE(std::holds_alternative<LoadedMesh>(loaded)) << std::get<MeshError>(loaded).message;
  const LoadedMesh& mesh = std::get<LoadedMesh>(loaded);

  const spectral::LaplaceOperators ops = spectral::laplaceOperators(mesh.V, mesh.F);
  const spectral::SparseMatrix& S = ops.stiffness;
  const double scale = S.coeffs().cwiseAbs().maxCoeff();
  ASSERT_TRUE(S.coeffs().allFinite());
  ASSERT_TRUE(ops.mass.allFinite());
  EXPECT_GT(ops.mass.minCoeff(), 0.0);
  EXPECT_LT((S * Eigen::VectorXd::Ones(S.rows())).cwiseAbs().maxCoeff(), 1e-10 * scale);
  const spectral::SparseMatrix asymmetry = S - spectral::SparseMatrix(S.transpose());
  EXPECT_LE(asymmetry.coeffs().cwiseAbs().maxCoeff(), 1e-14 * scale);
}

INSTANTIATE_TEST_SUITE_P(Assets, RealMeshOperators,
                         ::testing::Values("lion.off", "elephant.off", "ChineseDragon-10kv.off", "dragon_vrip_res4.ply",
                                           "dragon_vrip_res3.ply", "dragon_vrip_res2.ply"));

}  // namespace
}  // namespace sc::model
