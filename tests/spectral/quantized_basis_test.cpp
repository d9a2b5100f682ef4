// QuantizedBasis (K in int16 with a scale per column): the quantiser's range and error, the int16 kernel against a
// double reference, and the acceptance check of issue 17 on the real meshes: over the loss experiment's drag, the
// positions reconstructed from the quantised K of every level stay within 1e-4 of the bounding-box diagonal of the
// positions reconstructed from float32 K.

#include "spectral/quantized_basis.h"
#include "model/mesh_decimation.h"
#include "model/mesh_loader.h"
#include "spectral/basis_pipeline.h"
#include "spectral/hausdorff.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/resolution_level.h"
#include "spectral/spectral_deformer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <vector>

namespace sc::spectral {
namespace {

double maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, std::abs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
  return worst;
}

TEST(QuantizedBasis, EntriesSpanTheLevelRangePerColumnWithinHalfAStep) {
  std::srand(3);
  Eigen::MatrixXd K = Eigen::MatrixXd::Random(500, 7);
  K.col(2) *= 1e-6;    // a tiny column keeps its own scale
  K.col(4).setZero();  // an all-zero column: scale 0
  K(17, 5) = -250.0;   // one huge entry (a speck's constant mode) sets its column's scale
  const QuantizedBasis Q = quantizeBasis(K);
  ASSERT_EQ(Q.rows(), 500);
  ASSERT_EQ(Q.cols(), 7);
  EXPECT_EQ(Q.scale(4), 0.0f);
  EXPECT_EQ(Q.Q.col(4).cwiseAbs().maxCoeff(), 0);
  EXPECT_EQ(Q.Q(17, 5), -kQuantizedBasisLevels);
  for (Eigen::Index j = 0; j < K.cols(); ++j) {
    if (j == 4) continue;
    EXPECT_EQ(Q.Q.col(j).cast<int>().cwiseAbs().maxCoeff(), kQuantizedBasisLevels)
        << "column " << j << " uses the full range";
    const double step = Q.scale(j);
    for (Eigen::Index i = 0; i < K.rows(); ++i)
      ASSERT_LE(std::abs(Q(i, j) - K(i, j)), 0.5 * step + 2e-7 * kQuantizedBasisLevels * step)
          << "(" << i << ", " << j << ")";
  }
  EXPECT_EQ(dequantized(Q)(17, 5), Q(17, 5));
  EXPECT_EQ(Q.row(17)(5), Q(17, 5));
}

TEST(QuantizedBasis, Int16KernelEqualsTheDoubleReferenceOfTheDequantisedBasis) {
  for (const Eigen::Index m : {1, 7, 16, 33, 100}) {
    std::srand(static_cast<unsigned>(m));
    const QuantizedBasis K = quantizeBasis(Eigen::MatrixXd::Random(301, m));
    const Eigen::MatrixXd rest = Eigen::MatrixXd::Random(301, 3);
    const Eigen::MatrixXf Z = Eigen::MatrixXf::Random(m, 3);
    const Eigen::MatrixXd Kd = K.Q.cast<double>() * K.scale.cast<double>().asDiagonal();
    const Eigen::MatrixXd expected = rest.cast<float>().cast<double>() + Kd * Z.cast<double>();
    const double scale = (Kd.cwiseAbs() * Z.cast<double>().cwiseAbs()).maxCoeff();
    for (const KernelLoop loop : {KernelLoop::Fastest, KernelLoop::Portable})
      for (const int threads : {1, 2}) {
        std::vector<float> out(3 * 301);
        reconstructInterleaved(K, interleavedPositions(rest), Z, out, threads, loop);
        double error = 0.0;
        for (Eigen::Index i = 0; i < expected.rows(); ++i)
          for (int c = 0; c < 3; ++c)
            error = std::max(error, std::abs(out[static_cast<std::size_t>(3 * i + c)] - expected(i, c)));
        EXPECT_LE(error, 1e-5 * scale) << "m = " << m << ", threads = " << threads << ", "
                                       << kernelLoopDescription(loop);
      }
  }
}

TEST(QuantizedBasis, PositionErrorStaysWithinTheStatedBound) {
  std::srand(9);
  const Eigen::MatrixXd K = Eigen::MatrixXd::Random(2000, 40);
  const QuantizedBasis Q = quantizeBasis(K);
  const RowMatrixXf Kf = K.cast<float>();
  const std::vector<float> rest(3 * 2000, 0.0f);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::MatrixXf Z = Eigen::MatrixXf::Random(40, 3);
    std::vector<float> a(rest.size()), b(rest.size());
    reconstructInterleaved(Kf, rest, Z, a);
    reconstructInterleaved(Q, rest, Z, b);
    const double bound = quantizationBound(Q, Z);
    EXPECT_GT(maxDifference(a, b), 0.0) << "quantisation changes something";
    EXPECT_LE(maxDifference(a, b), bound + 1e-5 * bound * 40) << "trial " << trial;
  }
}

// === the real meshes: the loss experiment's drag (experiments/loss: a handle sphere of 5% of the rest bbox diagonal
// around the vertex with the largest x, anchors everything farther than 40%, moved by 15% of the diagonal along +y
// over 3 s at 30 fps and back), solved on the full mesh; every frame's Z reconstructed at every level (the host's
// ladder and the full resolution) with float32 K = P·H and with the quantised K.

std::vector<int> within(const Eigen::MatrixXd& V, Eigen::Index centre, double radius, bool inside) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (((V.row(i) - V.row(centre)).norm() <= radius) == inside) out.push_back(static_cast<int>(i));
  return out;
}

std::vector<Eigen::MatrixXf> lossDragCoefficients(const BasisComputation& basis, const Eigen::MatrixXd& V) {
  const double diagonal = boundingBoxDiagonal(V);
  Eigen::Index extremity = 0;
  V.col(0).maxCoeff(&extremity);
  SpectralDeformer deformer(basis.result.basis, basis.operators, V);
  EXPECT_TRUE(deformer.setConstraints(ConstraintSet{{HandleGroup{within(V, extremity, 0.05 * diagonal, true)}},
                                                    within(V, extremity, 0.4 * diagonal, false)}));
  std::vector<Eigen::MatrixXf> Zs;
  for (int frame = 0; frame <= 180; ++frame) {  // 6 s at 30 fps
    const double t = frame / 30.0;
    HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.15 * diagonal * (t <= 3.0 ? t / 3.0 : (6.0 - t) / 3.0), 0.0);
    const HandleTransform poses[] = {pose};
    Zs.push_back(deformer.solve(poses).cast<float>());
  }
  return Zs;
}

class RealMeshQuantizedBasis : public ::testing::TestWithParam<const char*> {};

TEST_P(RealMeshQuantizedBasis, EveryLevelStaysWithin1e4OfTheDiagonalOfFloatKOverTheLossDrag) {
  const std::filesystem::path path = std::filesystem::path(SHAPECAST_ASSETS_DIR) / GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not fetched (run scripts/fetch-meshes.sh)";
  const model::MeshLoadResult loaded = model::loadMesh(path);
  ASSERT_TRUE(std::holds_alternative<model::LoadedMesh>(loaded)) << std::get<model::MeshError>(loaded).message;
  const model::LoadedMesh& mesh = std::get<model::LoadedMesh>(loaded);
  BasisOptions options;
  options.m = 100;
  const BasisComputation basis = basisForMesh(mesh.V, mesh.F, options, std::nullopt);
  ASSERT_TRUE(basis.result.ok()) << basis.result.message;
  const Eigen::MatrixXd& H = basis.result.basis.vectors;
  const double diagonal = boundingBoxDiagonal(mesh.V);
  const std::vector<Eigen::MatrixXf> Zs = lossDragCoefficients(basis, mesh.V);
  ASSERT_EQ(Zs.size(), 181u);

  std::vector<ResolutionLevel> levels;
  levels.push_back(fullResolutionLevel(mesh.V, mesh.F, H));
  const std::vector<int> targets = model::levelTargets(static_cast<int>(mesh.V.rows()));
  for (const model::DecimatedMesh& low : model::resolutionLadder(mesh.V, mesh.F, targets))
    levels.push_back(resolutionLevel(mesh.V, mesh.F, H, low.V, low.F));
  ASSERT_GE(levels.size(), 2u);
  for (const ResolutionLevel& level : levels) {
    const RowMatrixXf floatK = (level.P * H).cast<float>();
    const std::vector<float> rest = interleavedPositions(level.restV);
    std::vector<float> exact(rest.size()), quantised(rest.size());
    double worst = 0.0, moved = 0.0;
    for (const Eigen::MatrixXf& Z : Zs) {
      reconstructInterleaved(floatK, rest, Z, exact);
      reconstructInterleaved(level.K, rest, Z, quantised);
      worst = std::max(worst, maxDifference(exact, quantised));
      moved = std::max(moved, maxDifference(exact, rest));
    }
    std::cout << "[ report   ] " << GetParam() << " level n' = " << level.restV.rows() << ": max position error "
              << worst / diagonal << " of the diagonal (drag moves up to " << moved / diagonal << ")\n";
    EXPECT_GT(moved, 0.05 * diagonal) << "the drag really deforms the level";
    EXPECT_LT(worst, 1e-4 * diagonal) << "n' = " << level.restV.rows();
  }
}

INSTANTIATE_TEST_SUITE_P(Assets, RealMeshQuantizedBasis,
                         ::testing::Values("lion.off", "elephant.off", "ChineseDragon-10kv.off", "dragon_vrip_res4.ply",
                                           "dragon_vrip_res3.ply", "dragon_vrip_res2.ply"));

}  // namespace
}  // namespace sc::spectral
