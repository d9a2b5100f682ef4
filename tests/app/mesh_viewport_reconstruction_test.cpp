// Tests for the viewport's two reconstruction paths (src/app/gui/viewport/gpu_reconstructor.cpp and
// cpu_reconstructor.cpp): the GPU path X' = X̂' + K·Z agrees with the CPU kernel, draws the same silhouette and keeps
// picking on the reconstructed shape; the viewport holds the shared display level (needs an X server with GL;
// skipped otherwise).

#include "app/gui/mesh_viewport.h"

#include "app_test_support.h"
#include "spectral/reconstruction_kernel.h"
#include "synthetic_basis.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QColor>
#include <QTest>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace {

using sc::app::MeshViewport;
using sc::app::ReconstructionPath;
using sc::testing::randomCoefficients;
using sc::testing::syntheticBasis;

double diagonalOf(const std::vector<float>& xyz) {
  Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>> P(
      xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  return static_cast<double>((P.colwise().maxCoeff() - P.colwise().minCoeff()).norm());
}

double maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::abs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
  }
  return worst;
}

class MeshViewportReconstructionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) {
      GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
    }
    m_sphere = sc::testing::icosphere(4, 2.0, Eigen::Vector3d(10, -5, 3));
    m_rest = sc::spectral::interleavedPositions(m_sphere.V);
    m_viewport.resize(320, 240);
    m_viewport.setMesh(m_sphere.V, m_sphere.F);
    m_viewport.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&m_viewport));
    m_background = m_viewport.grabFramebuffer();
  }

  // The display level of the sphere with basis K, as a session hands it to the viewport.
  sc::spectral::SharedDisplayLevel levelWith(const sc::spectral::QuantizedBasis& K) const {
    return sc::spectral::makeDisplayLevel({m_sphere.V, m_sphere.F, {}, K});
  }

  // The CPU kernel's positions for (K, Z).
  std::vector<float> cpuPositions(const sc::spectral::QuantizedBasis& K, const Eigen::MatrixXf& Z) const {
    std::vector<float> out(m_rest.size());
    sc::spectral::reconstructInterleaved(K, m_rest, Z, out);
    return out;
  }

  sc::testing::GeneratedMesh m_sphere;
  std::vector<float> m_rest;
  MeshViewport m_viewport;
  QImage m_background;
};

// setDisplayLevel() copies nothing per vertex on the GUI thread (issue 19 item 3): the vertex buffers show the
// level's own rest positions, normals and faces (spectral::DisplayGeometry, computed with the level) and the picture
// of the rest shape is setMesh()'s. The first CPU frame of the full mesh writes positions of its own; the level's
// arrays are never written.
TEST_F(MeshViewportReconstructionTest, SetDisplayLevelShowsTheLevelsOwnArraysUntilAFrameWritesItsOwn) {
  const QImage plain = m_viewport.grabFramebuffer();  // setMesh()'s rest shape
  const int m = 12;
  const auto K = syntheticBasis(m_sphere.V, m, 0.05f);
  const sc::spectral::SharedDisplayLevel level = levelWith(K);
  const std::vector<float> levelRest = level->geometry.rest;
  const std::vector<float> levelNormals = level->geometry.normals;
  m_viewport.setReconstructionPath(ReconstructionPath::Cpu);
  m_viewport.setDisplayLevel(level);
  EXPECT_TRUE(m_viewport.showsLevelArrays());
  EXPECT_EQ(m_viewport.triangleCount(), m_sphere.F.rows());
  const double diagonal = diagonalOf(m_rest);
  EXPECT_LE(maxDifference(m_viewport.hostPositions(), m_rest), 1e-5 * diagonal);
  const QImage shown = m_viewport.grabFramebuffer();
  ASSERT_EQ(shown.size(), plain.size());
  int differ = 0;
  for (int y = 0; y < shown.height(); ++y)
    for (int x = 0; x < shown.width(); ++x) differ += shown.pixel(x, y) != plain.pixel(x, y) ? 1 : 0;
  EXPECT_LT(differ, shown.width() * shown.height() / 200) << "the level's rest shape looks like setMesh()'s";
  EXPECT_TRUE(m_viewport.showsLevelArrays()) << "a paint uploads them, nothing writes them";

  const Eigen::MatrixXf Z = randomCoefficients(m, 1.0f, 5U);
  m_viewport.showFrame({1, Z});
  static_cast<void>(m_viewport.grabFramebuffer());  // a frame of the full mesh on the CPU path
  EXPECT_FALSE(m_viewport.showsLevelArrays());
  EXPECT_LE(maxDifference(m_viewport.hostPositions(), cpuPositions(K, Z)), 1e-5 * diagonal);
  EXPECT_EQ(level->geometry.rest, levelRest) << "the shared level is immutable";
  EXPECT_EQ(level->geometry.normals, levelNormals);
}

TEST_F(MeshViewportReconstructionTest, GpuAgreesWithCpuWithin1e5OfTheDiagonal) {
  ASSERT_TRUE(m_viewport.gpuReconstructionAvailable());
  for (const int m : {100, 7, 1}) {  // 7 and 1: K padded to a multiple of 4 columns
    const auto K = syntheticBasis(m_sphere.V, m, 0.05f);
    const Eigen::MatrixXf Z = randomCoefficients(m, 1.0f, 11U + static_cast<unsigned>(m));
    m_viewport.setDisplayLevel(levelWith(K));
    m_viewport.setReconstructionPath(ReconstructionPath::Gpu);
    ASSERT_EQ(m_viewport.reconstructionPath(), ReconstructionPath::Gpu);
    m_viewport.showFrame({1, Z});
    const std::vector<float> expected = cpuPositions(K, Z);
    const std::vector<float> gpu = m_viewport.gpuReconstructedPositions();
    ASSERT_EQ(gpu.size(), expected.size()) << "m = " << m;
    const double diagonal = diagonalOf(expected);
    EXPECT_LE(maxDifference(gpu, expected), 1e-5 * diagonal) << "m = " << m;
    EXPECT_GT(maxDifference(expected, m_rest), 1e-3 * diagonal) << "the frame really moves the mesh, m = " << m;
    // The host copy used for picking agrees too (reconstructed lazily on the CPU).
    EXPECT_LE(maxDifference(m_viewport.hostPositions(), expected), 1e-5 * diagonal) << "m = " << m;
    // The CPU path of the viewport shows the same positions.
    m_viewport.setReconstructionPath(ReconstructionPath::Cpu);
    EXPECT_LE(maxDifference(m_viewport.hostPositions(), expected), 1e-5 * diagonal) << "m = " << m;
  }
}

TEST_F(MeshViewportReconstructionTest, BothPathsDrawTheSameSilhouette) {
  const int m = 40;
  const auto K = syntheticBasis(m_sphere.V, m, 0.08f);
  const Eigen::MatrixXf Z = randomCoefficients(m, 1.0f, 3U);
  m_viewport.setDisplayLevel(levelWith(K));
  m_viewport.showFrame({1, Z});
  const QImage cpu = m_viewport.grabFramebuffer();
  m_viewport.setReconstructionPath(ReconstructionPath::Gpu);
  ASSERT_EQ(m_viewport.reconstructionPath(), ReconstructionPath::Gpu);
  const QImage gpu = m_viewport.grabFramebuffer();
  ASSERT_EQ(cpu.size(), gpu.size());
  int covered = 0;
  int mismatched = 0;
  for (int y = 0; y < cpu.height(); ++y) {
    for (int x = 0; x < cpu.width(); ++x) {
      const bool inCpu = cpu.pixel(x, y) != m_background.pixel(x, y);
      const bool inGpu = gpu.pixel(x, y) != m_background.pixel(x, y);
      covered += inCpu ? 1 : 0;
      mismatched += inCpu != inGpu ? 1 : 0;
    }
  }
  EXPECT_GT(covered, cpu.width() * cpu.height() / 20) << "the mesh is on screen";
  EXPECT_LE(mismatched, covered / 100) << "the silhouettes agree (shading may differ: face vs vertex normals)";
  // Lit, not black: the face normals give the same light level as the vertex normals, on average.
  double cpuLight = 0.0;
  double gpuLight = 0.0;
  for (int y = 0; y < cpu.height(); ++y) {
    for (int x = 0; x < cpu.width(); ++x) {
      if (cpu.pixel(x, y) != m_background.pixel(x, y) && gpu.pixel(x, y) != m_background.pixel(x, y)) {
        cpuLight += QColor(cpu.pixel(x, y)).lightness();
        gpuLight += QColor(gpu.pixel(x, y)).lightness();
      }
    }
  }
  EXPECT_NEAR(gpuLight / cpuLight, 1.0, 0.05);
}

TEST_F(MeshViewportReconstructionTest, PositionsReplaceCoefficientsAndSetMeshDropsTheBasis) {
  const int m = 12;
  const auto K = syntheticBasis(m_sphere.V, m, 0.1f);
  m_viewport.setDisplayLevel(levelWith(K));
  m_viewport.setReconstructionPath(ReconstructionPath::Gpu);
  m_viewport.showFrame({1, randomCoefficients(m, 1.0f, 5U)});
  m_viewport.setPositionsInterleaved(m_rest);
  EXPECT_LE(maxDifference(m_viewport.hostPositions(), m_rest), 1e-5) << "explicit positions win";
  EXPECT_TRUE(m_viewport.hasReconstructionBasis());
  m_viewport.setMesh(m_sphere.V, m_sphere.F);
  EXPECT_FALSE(m_viewport.hasReconstructionBasis());
  EXPECT_TRUE(m_viewport.gpuReconstructedPositions().empty());
}

TEST_F(MeshViewportReconstructionTest, TooLargeABasisFallsBackToTheCpu) {
  const int m = sc::app::GpuReconstructor::kMaxBasisSize + 4;
  const auto K = syntheticBasis(m_sphere.V, m, 0.01f);
  m_viewport.setDisplayLevel(levelWith(K));
  m_viewport.setReconstructionPath(ReconstructionPath::Gpu);
  EXPECT_EQ(m_viewport.reconstructionPath(), ReconstructionPath::Cpu);
  const Eigen::MatrixXf Z = randomCoefficients(m, 1.0f, 9U);
  m_viewport.showFrame({1, Z});
  EXPECT_LE(maxDifference(m_viewport.hostPositions(), cpuPositions(K, Z)), 1e-6);
}

TEST_F(MeshViewportReconstructionTest, HoldsTheSharedLevelAndReadsItsKInPlace) {
  const int m = 9;
  const auto level = levelWith(syntheticBasis(m_sphere.V, m, 0.05f));
  const std::int16_t* K = level->level.K.Q.data();
  m_viewport.setDisplayLevel(level);
  EXPECT_EQ(m_viewport.displayLevel(), level) << "held by pointer, not copied";
  EXPECT_EQ(m_viewport.displayLevel()->level.K.Q.data(), K);
  EXPECT_LE(maxDifference(m_viewport.hostPositions(), m_rest), 1e-5) << "the rest shape before the first frame";
  const Eigen::MatrixXf Z = randomCoefficients(m, 1.0f, 4U);
  for (const ReconstructionPath path : {ReconstructionPath::Cpu, ReconstructionPath::Gpu}) {
    m_viewport.setReconstructionPath(path);
    m_viewport.showFrame({2, Z});
    EXPECT_LE(maxDifference(m_viewport.hostPositions(), cpuPositions(level->level.K, Z)), 1e-5);
    m_viewport.showFrame({3, Eigen::MatrixXf()});
    EXPECT_LE(maxDifference(m_viewport.hostPositions(), m_rest), 1e-5) << "an empty Z shows the rest shape";
  }
  m_viewport.showFrame({4, Eigen::MatrixXf::Ones(m + 1, 3)});
  EXPECT_LE(maxDifference(m_viewport.hostPositions(), m_rest), 1e-5) << "a Z of another size is ignored";
  m_viewport.setDisplayLevel(nullptr);
  EXPECT_EQ(m_viewport.vertexCount(), 0);
  EXPECT_EQ(level.use_count(), 1) << "the viewport let go of the level";
}

}  // namespace
