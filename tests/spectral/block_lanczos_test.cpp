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
#include <memory>
#include <numbers>
#include <vector>

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

/// Restores OpenBLAS's thread count on leaving the scope (a failed assertion returns early).
class BlasThreadsRestored {
 public:
  BlasThreadsRestored() : m_original(openblas_get_num_threads()) {}
  ~BlasThreadsRestored() { openblas_set_num_threads(m_original); }
  BlasThreadsRestored(const BlasThreadsRestored&) = delete;
  BlasThreadsRestored& operator=(const BlasThreadsRestored&) = delete;

 private:
  int m_original;
};

TEST(BlockLanczos, TheLargeMeshRunUsesOneOpenBlasThreadAndRestoresTheSetting) {
  if (openblas_get_num_threads == nullptr || openblas_set_num_threads == nullptr) GTEST_SKIP() << "not OpenBLAS";
  const BlasThreadsRestored restored;
  openblas_set_num_threads(2);
  if (openblas_get_num_threads() != 2) GTEST_SKIP() << "this OpenBLAS build runs on one thread only";
  {
    const detail::SingleThreadedBlas one;
    EXPECT_EQ(openblas_get_num_threads(), 1);
  }
  EXPECT_EQ(openblas_get_num_threads(), 2);
  {  // holders that overlap (as on two threads): the setting comes back when the last one leaves
    auto first = std::make_unique<detail::SingleThreadedBlas>();
    const detail::SingleThreadedBlas second;
    first.reset();
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
}

TEST(BlockLanczos, TheLargeMeshRunConvergesToItsOwnTolerance) {
  // BasisOptions::largeMeshTolerance, not `tolerance`, decides when the large-mesh run stops: a tighter one costs
  // more solves and leaves smaller residuals.
  const Problem problem = torusProblem();
  BasisOptions loose;
  loose.tolerance = 1e-12;  // ignored by this run
  loose.largeMeshTolerance = 1e-4;
  BasisOptions tight = loose;
  tight.tolerance = 1e-4;
  tight.largeMeshTolerance = 1e-12;
  const BasisResult a = detail::blockLanczosEigenpairs(problem.ops, 20, problem.bottomShift, loose);
  const BasisResult b = detail::blockLanczosEigenpairs(problem.ops, 20, problem.bottomShift, tight);
  ASSERT_TRUE(a.ok()) << a.message;
  ASSERT_TRUE(b.ok()) << b.message;
  EXPECT_LT(a.operatorApplications, b.operatorApplications);
  const auto worst = [&problem](const BasisResult& run) {
    const Eigen::MatrixXd& h = run.basis.vectors;
    return detail::relativeResiduals(problem.ops.stiffness * h, problem.ops.mass.asDiagonal() * h, problem.ops.mass,
                                     run.basis.eigenvalues, problem.bottomShift)
        .maxCoeff();
  };
  EXPECT_LT(worst(b), worst(a));
}

/// Six equal unit spheres side by side (6 × 162 vertices): λ = 0 six times, then the first non-constant harmonic
/// eighteen times, then the next thirty times.
struct SixSpheres {
  LaplaceOperators ops;
  double sigma{};
  Eigen::VectorXd exact;         ///< the dense generalised eigenproblem's first `kPairs` eigenvalues
  Eigen::MatrixXd exactVectors;  ///< its first 60 eigenvectors, M-orthonormal
  static constexpr int kPairs = 30;

  SixSpheres() {
    testing::GeneratedMesh mesh = testing::icosphere(2);
    for (int copy = 1; copy < 6; ++copy) mesh = testing::joined(mesh, testing::icosphere(2, 1.0, {3.0 * copy, 0, 0}));
    ops = laplaceOperators(mesh.V, mesh.F);
    sigma = -4.0 * std::numbers::pi / ops.totalArea;
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(Eigen::MatrixXd(ops.stiffness),
                                                                          Eigen::MatrixXd(ops.mass.asDiagonal()));
    if (dense.info() != Eigen::Success) return;
    exact = dense.eigenvalues().head(kPairs);
    exactVectors = dense.eigenvectors().leftCols(60);
  }

  /// Every eigenvalue equal to the dense one (relative to |λ| + |σ|), M-orthonormal vectors with small residuals (the
  /// large-mesh run converges to BasisOptions::largeMeshTolerance = 1e-8, which left 7.7e-7 on the 437k scan).
  void expectExact(const BasisResult& run) const {
    ASSERT_EQ(exact.size(), kPairs);
    ASSERT_TRUE(run.ok()) << run.message;
    ASSERT_EQ(run.basis.eigenvalues.size(), kPairs);
    EXPECT_LE(((run.basis.eigenvalues - exact).array().abs() / (exact.array().abs() + std::abs(sigma))).maxCoeff(),
              1e-8);
    EXPECT_LE(orthonormalityError(run.basis.vectors, ops.mass), 1e-8);
    const Eigen::MatrixXd& h = run.basis.vectors;
    EXPECT_LE(
        detail::relativeResiduals(ops.stiffness * h, ops.mass.asDiagonal() * h, ops.mass, run.basis.eigenvalues, sigma)
            .maxCoeff(),
        1e-6);
  }
};

TEST(BlockLanczos, SixEqualSpheresInTheOneRunGiveEveryCopyOfEachEigenvalue) {
  // A multiplicity above the block's four columns must still come out whole: the run alone misses copies, which the
  // large-mesh run's counts find.
  const SixSpheres spheres;
  ASSERT_LE(spheres.exact[23] / spheres.exact[6], 1.0 + 1e-6) << "the first harmonics form one cluster of 18";
  detail::ShiftInvertOperator op(spheres.ops.stiffness, spheres.ops.mass, {});
  const BasisResult alone = detail::nearestPairs(op, spheres.ops.mass, SixSpheres::kPairs, spheres.sigma, {});
  ASSERT_TRUE(alone.ok()) << alone.message;
  EXPECT_GT((alone.basis.eigenvalues - spheres.exact).cwiseAbs().maxCoeff(), 1.0) << "the run alone missed no copy";
  const BasisResult run = detail::blockLanczosEigenpairs(spheres.ops, SixSpheres::kPairs, spheres.sigma, {});
  spheres.expectExact(run);
  EXPECT_GT(run.operatorApplications, alone.operatorApplications);  // the deflated runs' solves are counted
}

TEST(RepeatedEigenvalues, ASingleVectorRunIsCountedWholeAndCompleted) {
  // Spectra's fallback may miss copies of any multiplicity, so everything up to index m − 1 is counted. Its result
  // here is made up from exact pairs: the six zeros, one copy of the first harmonic and one of the second in the
  // place of the first's second copy, so that no cluster reaches four and the block rule sees nothing wrong.
  const SixSpheres spheres;
  ASSERT_EQ(spheres.exactVectors.cols(), 60);
  constexpr int pairs = 8;
  const std::vector<int> picked{0, 1, 2, 3, 4, 5, 6, 24};
  const auto madeUp = [&spheres, &picked] {
    BasisResult result;
    result.status = BasisStatus::Ok;
    result.basis.eigenvalues.resize(pairs);
    result.basis.vectors.resize(spheres.exactVectors.rows(), pairs);
    for (int i = 0; i < pairs; ++i) {
      const int index = picked[static_cast<std::size_t>(i)];
      result.basis.vectors.col(i) = spheres.exactVectors.col(index);
      result.basis.eigenvalues[i] = spheres.exact[index];
    }
    return result;
  };
  detail::ShiftInvertOperator op(spheres.ops.stiffness, spheres.ops.mass, {});
  BasisResult asBlock = madeUp();
  detail::completeRepeatedEigenvalues(op, spheres.ops.mass, pairs, spheres.sigma, BasisOptions{}, false, asBlock);
  ASSERT_TRUE(asBlock.ok()) << asBlock.message;
  EXPECT_EQ(asBlock.basis.eigenvalues, madeUp().basis.eigenvalues) << "the block rule counts the zeros only";
  BasisResult asSingle = madeUp();
  detail::completeRepeatedEigenvalues(op, spheres.ops.mass, pairs, spheres.sigma, BasisOptions{}, true, asSingle);
  ASSERT_TRUE(asSingle.ok()) << asSingle.message;
  const Eigen::VectorXd expected = spheres.exact.head(pairs);  // six zeros, then the first harmonic twice
  EXPECT_LE((asSingle.basis.eigenvalues - expected).cwiseAbs().maxCoeff(), 1e-8 * (2.0 + std::abs(spheres.sigma)));
  EXPECT_LE(orthonormalityError(asSingle.basis.vectors, spheres.ops.mass), 1e-8);
}

TEST(RepeatedEigenvalues, ACancelBeforeACountIsHonoured) {
  const SixSpheres spheres;
  detail::ShiftInvertOperator op(spheres.ops.stiffness, spheres.ops.mass, {});
  BasisResult run = detail::nearestPairs(op, spheres.ops.mass, SixSpheres::kPairs, spheres.sigma, {});
  ASSERT_TRUE(run.ok()) << run.message;
  BasisOptions options;
  int calls = 0;
  options.progress = [&calls](double) {
    ++calls;
    return false;
  };
  detail::completeRepeatedEigenvalues(op, spheres.ops.mass, SixSpheres::kPairs, spheres.sigma, options, false, run);
  EXPECT_EQ(run.status, BasisStatus::Cancelled);
  EXPECT_EQ(calls, 1);  // asked once, before the first count (the zeros' cluster)
  EXPECT_EQ(run.basis.size(), 0);
}

TEST(RepeatedEigenvalues, AClusterIsTheValuesWithinOneGapOfItsFirst) {
  const double scale = 1.0;
  Eigen::VectorXd values(8);
  values << 0.0, 1e-9, 2.0, 2.0 + 1e-7, 2.0 + 2e-7, 2.0 + 3e-7, 3.0, 3.0 + 1e-2;
  EXPECT_EQ(detail::clusterEnd(values, 0, scale), 1);
  EXPECT_EQ(detail::clusterEnd(values, 2, scale), 5);
  EXPECT_EQ(detail::clusterEnd(values, 6, scale), 6);  // 3 and 3.01 are 2.5e-3 apart relatively
  EXPECT_EQ(detail::clusterEnd(values, 7, scale), 7);
  // a chain of steps each under the gap is cut where it leaves the first value's gap: 1e-4·(|λ| + 1) ≈ 2e-4 here
  Eigen::VectorXd chain(4);
  chain << 1.0, 1.0 + 1.5e-4, 1.0 + 3e-4, 1.0 + 4.5e-4;
  EXPECT_EQ(detail::clusterEnd(chain, 0, scale), 1);
  EXPECT_EQ(detail::clusterEnd(chain, 2, scale), 3);
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
