// Block shift-invert Lanczos (the solver inside each spectrum slice) against Spectra's restarted Lanczos on the same
// factor: bottom and interior shifts, solves on several threads, and how it ends when it cannot finish (columns used
// up, cancellation); the large-mesh run's OpenBLAS setting and its completion of repeated eigenvalues.

#include "spectral/block_lanczos.h"
#include "spectral/harmonic_basis.h"
#include "spectral/lanczos_solver.h"
#include "spectral/large_mesh_eigenpairs.h"
#include "spectral/repeated_eigenvalues.h"
#include "spectral/single_threaded_blas.h"
#include "spectral/subspace_iteration.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>

namespace sc::spectral {
namespace {

struct Problem {
  LaplaceOperators ops;
  double bottomShift{};  ///< σ < 0, as manifoldHarmonicBasis() uses
};

Problem torusProblem(int major = 48, int minor = 16) {  // 768 vertices by default
  const auto mesh = testing::torus(major, minor);
  Problem problem{laplaceOperators(mesh.V, mesh.F), 0.0};
  problem.bottomShift = -4.0 * std::numbers::pi / problem.ops.totalArea;
  return problem;
}

BasisResult spectraPairs(const Problem& problem, int pairs, double sigma) {
  detail::ShiftInvertOperator op(problem.ops.stiffness, problem.ops.mass, {});
  return detail::lanczosNearestPairs(op, problem.ops.mass, pairs, 5 * pairs / 2, sigma, BasisOptions{});
}

BasisResult blockPairs(const Problem& problem, int pairs, double sigma, int maxColumns = 0, int threads = 1) {
  detail::ShiftInvertOperator op(problem.ops.stiffness, problem.ops.mass, {});
  op.setSolveThreads(threads);
  return detail::blockLanczosNearestPairs(op, problem.ops.mass, pairs, maxColumns > 0 ? maxColumns : 4 * pairs + 40,
                                          sigma, BasisOptions{});
}

/// Same eigenvalues (relative to |λ| + |σ|), M-orthonormal vectors with small residuals.
void expectSamePairs(const Problem& problem, const BasisResult& block, const BasisResult& spectra, double sigma) {
  ASSERT_TRUE(block.ok()) << block.message;
  ASSERT_TRUE(spectra.ok()) << spectra.message;
  ASSERT_EQ(block.basis.eigenvalues.size(), spectra.basis.eigenvalues.size());
  const Eigen::VectorXd scale = spectra.basis.eigenvalues.cwiseAbs().array() + std::abs(sigma);
  EXPECT_LE((block.basis.eigenvalues - spectra.basis.eigenvalues).cwiseQuotient(scale).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::MatrixXd& h = block.basis.vectors;
  const Eigen::MatrixXd gram = h.transpose() * problem.ops.mass.asDiagonal() * h;
  EXPECT_LE((gram - Eigen::MatrixXd::Identity(h.cols(), h.cols())).cwiseAbs().maxCoeff(), 1e-10);
  const Eigen::VectorXd residuals = detail::relativeResiduals(
      problem.ops.stiffness * h, problem.ops.mass.asDiagonal() * h, problem.ops.mass, block.basis.eigenvalues, sigma);
  EXPECT_LE(residuals.maxCoeff(), 1e-7);
}

TEST(BlockLanczos, BottomOfTheSpectrumMatchesSpectra) {
  const Problem problem = torusProblem();
  const BasisResult block = blockPairs(problem, 40, problem.bottomShift);
  expectSamePairs(problem, block, spectraPairs(problem, 40, problem.bottomShift), problem.bottomShift);
  EXPECT_EQ(block.operatorApplications % detail::kLanczosBlock, 0);  // solves come in whole blocks
}

TEST(BlockLanczos, SolvesAndSweepsOnThreeThreadsMatchSpectra) {
  // the large-mesh path: each block's columns solved on their own threads, the row-band sweeps (local and full
  // passes) and the Ritz vectors' bands split too: 4,608 vertices are 9 bands of 512 rows and 3 bands of 2,048
  const Problem problem = torusProblem(96, 48);
  const BasisResult block = blockPairs(problem, 40, problem.bottomShift, 0, 3);
  expectSamePairs(problem, block, spectraPairs(problem, 40, problem.bottomShift), problem.bottomShift);
}

TEST(BlockLanczos, TheLargeMeshRunUsesOneOpenBlasThreadAndRestoresTheSetting) {
  if (openblas_get_num_threads == nullptr || openblas_set_num_threads == nullptr) GTEST_SKIP() << "not OpenBLAS";
  const int original = openblas_get_num_threads();
  openblas_set_num_threads(2);
  {
    const detail::SingleThreadedBlas one;
    EXPECT_EQ(openblas_get_num_threads(), 1);
  }
  EXPECT_EQ(openblas_get_num_threads(), 2);
  const Problem problem = torusProblem();
  BasisOptions options;
  int calls = 0;
  options.progress = [&calls](double) {
    EXPECT_EQ(openblas_get_num_threads(), 1);  // called from the run's solves
    ++calls;
    return true;
  };
  const BasisResult run = detail::blockLanczosEigenpairs(problem.ops, 20, problem.bottomShift, options);
  ASSERT_TRUE(run.ok()) << run.message;
  EXPECT_GT(calls, 0);
  EXPECT_EQ(openblas_get_num_threads(), 2);
  openblas_set_num_threads(original);
}

TEST(BlockLanczos, SixEqualSpheresInTheOneRunGiveEveryCopyOfEachEigenvalue) {
  // The large-mesh run has no count check: a multiplicity above the block's four columns (here 0 six times, then
  // the first non-constant harmonic eighteen times) must still come out whole. Reference: the dense generalised
  // eigenproblem of the same S and M (1,932 vertices).
  testing::GeneratedMesh mesh = testing::icosphere(2);
  for (int copy = 1; copy < 6; ++copy) mesh = testing::joined(mesh, testing::icosphere(2, 1.0, {3.0 * copy, 0, 0}));
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(Eigen::MatrixXd(ops.stiffness),
                                                                        Eigen::MatrixXd(ops.mass.asDiagonal()));
  ASSERT_EQ(dense.info(), Eigen::Success);
  const int pairs = 30;  // 6 + 18, then into the next cluster of 30
  const double sigma = -4.0 * std::numbers::pi / ops.totalArea;
  const BasisResult run = detail::blockLanczosEigenpairs(ops, pairs, sigma, BasisOptions{});
  ASSERT_TRUE(run.ok()) << run.message;
  const Eigen::VectorXd expected = dense.eigenvalues().head(pairs);
  EXPECT_LE(((run.basis.eigenvalues - expected).array().abs() / (expected.array().abs() + std::abs(sigma))).maxCoeff(),
            1e-8);
  EXPECT_LE(expected[23] / expected[6], 1.0 + 1e-6) << "the spheres' first harmonics form one cluster of 18";
  EXPECT_LE(orthonormalityError(run.basis.vectors, ops.mass), 1e-8);
  const Eigen::MatrixXd& h = run.basis.vectors;
  EXPECT_LE(
      detail::relativeResiduals(ops.stiffness * h, ops.mass.asDiagonal() * h, ops.mass, run.basis.eigenvalues, sigma)
          .maxCoeff(),
      1e-7);
  EXPECT_GT(run.operatorApplications, 0);
}

TEST(RepeatedEigenvalues, LargestClusterCountsNeighboursWithinTheRelativeGap) {
  const double scale = 1.0;
  EXPECT_EQ(detail::largestCluster(Eigen::VectorXd(), scale), 0);
  EXPECT_EQ(detail::largestCluster(Eigen::VectorXd::Constant(1, 5.0), scale), 1);
  Eigen::VectorXd values(8);
  values << 0.0, 1e-9, 2.0, 2.0 + 1e-7, 2.0 + 2e-7, 2.0 + 3e-7, 3.0, 3.0 + 1e-2;
  EXPECT_EQ(detail::largestCluster(values, scale), 4);  // 2, four times; 3 and 3.01 are 3e-3 apart relatively
}

TEST(BlockLanczos, InteriorShiftFindsThePairsNearestItOnBothSides) {
  const Problem problem = torusProblem();
  const BasisResult bottom = spectraPairs(problem, 60, problem.bottomShift);
  ASSERT_TRUE(bottom.ok()) << bottom.message;
  const Eigen::VectorXd& lambda = bottom.basis.eigenvalues;
  int split = 35;  // a shift in a gap between the 35th and 36th eigenvalues (not inside a multiplet)
  while (lambda(split) - lambda(split - 1) < 1e-3 * lambda(split)) ++split;
  const double sigma = 0.5 * (lambda(split - 1) + lambda(split));
  const BasisResult block = blockPairs(problem, 16, sigma);
  expectSamePairs(problem, block, spectraPairs(problem, 16, sigma), sigma);
  EXPECT_LT((block.basis.eigenvalues.array() < sigma).count(), 16);  // pairs on both sides of the shift
  EXPECT_GT((block.basis.eigenvalues.array() < sigma).count(), 0);
}

TEST(BlockLanczos, UsingUpItsColumnsIsNotConverged) {
  const Problem problem = torusProblem();
  // pairs + 2 blocks of columns: far too few for 60 pairs to converge to 1e-10
  const BasisResult block = blockPairs(problem, 60, problem.bottomShift, 1);
  EXPECT_EQ(block.status, BasisStatus::NotConverged);
  EXPECT_NE(block.message.find("did not converge"), std::string::npos) << block.message;
  EXPECT_EQ(block.basis.size(), 0);
}

TEST(BlockLanczos, TooSmallAMeshIsNotConverged) {
  const auto mesh = testing::icosphere(1);  // 42 vertices: half of them cannot hold 30 pairs and two blocks
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  detail::ShiftInvertOperator op(ops.stiffness, ops.mass, {});
  const BasisResult block = detail::blockLanczosNearestPairs(op, ops.mass, 30, 200, -1.0, BasisOptions{});
  EXPECT_EQ(block.status, BasisStatus::NotConverged);
}

TEST(BlockLanczos, CancelledByTheSolveObserver) {
  const Problem problem = torusProblem();
  detail::ShiftInvertOperator op(problem.ops.stiffness, problem.ops.mass, [](int solves) { return solves < 10; });
  const BasisResult block =
      detail::blockLanczosNearestPairs(op, problem.ops.mass, 40, 200, problem.bottomShift, BasisOptions{});
  EXPECT_EQ(block.status, BasisStatus::Cancelled);
  EXPECT_EQ(block.operatorApplications, 10);
}

}  // namespace
}  // namespace sc::spectral
