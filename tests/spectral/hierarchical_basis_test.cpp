// The hierarchical eigensolver's own behaviour: fallback, cancellation, non-convergence, threads, aggregation.
// Its eigenpairs against the Lanczos reference: fast_eigensolvers_test.cpp.

#include "spectral/harmonic_basis.h"
#include "spectral/subspace_iteration.h"
#include "spectral/vertex_aggregation.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace sc::spectral {
namespace {

TEST(HierarchicalBasis, TooSmallToCoarsenFallsBackToLanczos) {
  const auto mesh = testing::icosphere(2);  // 162 vertices < 8(m + guard)
  BasisOptions options;
  options.m = 10;
  options.solver = BasisSolver::Hierarchical;
  const BasisResult r = manifoldHarmonicBasis(laplaceOperators(mesh.V, mesh.F), options);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.solver, BasisSolver::Lanczos);
  EXPECT_EQ(r.sweeps, 0);
}

TEST(HierarchicalBasis, CancelledFromTheProgressCallback) {
  const auto mesh = testing::icosphere(5);
  BasisOptions options;
  options.m = 30;
  options.solver = BasisSolver::Hierarchical;
  options.progress = [](double fraction) { return fraction < 0.2; };  // past the coarse level: inside the sweeps
  const BasisResult r = manifoldHarmonicBasis(laplaceOperators(mesh.V, mesh.F), options);
  EXPECT_EQ(r.status, BasisStatus::Cancelled);
}

TEST(HierarchicalBasis, NotConvergedIsReportedNotReturned) {
  const auto mesh = testing::icosphere(5);
  BasisOptions options;
  options.m = 30;
  options.solver = BasisSolver::Hierarchical;
  options.residualTolerance = 1e-300;  // unreachable
  options.maxSweeps = 3;
  const BasisResult r = manifoldHarmonicBasis(laplaceOperators(mesh.V, mesh.F), options);
  EXPECT_EQ(r.status, BasisStatus::NotConverged);
  EXPECT_EQ(r.basis.size(), 0);
}

TEST(SubspaceIteration, SolvesOnSeveralThreadsGiveTheSameBasisAsOne) {
  // every thread solves its own chunks of columns with its own CHOLMOD workspace on the shared factor: the
  // arithmetic per column is the same, so the result must be bit for bit the one of a single thread
  const auto mesh = testing::icosphere(4);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const double sigma = -4.0 * std::acos(-1.0) / ops.totalArea;
  const std::vector<AggregatedOperators> levels = aggregationHierarchy(ops, 100);
  ASSERT_FALSE(levels.empty());
  const Eigen::MatrixXd coarseStart = Eigen::MatrixXd::Random(levels[0].coarseSize(), 30);
  const Eigen::MatrixXd start = levels[0].prolongation * coarseStart;
  detail::SubspaceIterationOptions options;
  options.wanted = 20;
  options.threads = 1;
  const detail::SubspaceIterationResult one = detail::subspaceIteration(ops, sigma, start, options);
  options.threads = 3;
  const detail::SubspaceIterationResult three = detail::subspaceIteration(ops, sigma, start, options);
  ASSERT_EQ(one.status, detail::SubspaceIterationResult::Status::Converged);
  ASSERT_EQ(three.status, detail::SubspaceIterationResult::Status::Converged);
  EXPECT_EQ(one.solves, three.solves);
  EXPECT_EQ(one.eigenvalues, three.eigenvalues);
  EXPECT_EQ(one.vectors, three.vectors);
  EXPECT_LE(one.residuals.maxCoeff(), options.tolerance);
  EXPECT_EQ(one.guard.cols(), 10);
}

TEST(VertexAggregation, SmoothedGalerkinLevelsKeepAreaNullSpaceAndComponents) {
  const auto mesh = testing::twoSpheresAndATorus();
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const std::vector<AggregatedOperators> levels = aggregationHierarchy(ops, 100);
  ASSERT_FALSE(levels.empty());
  const Eigen::Index a = testing::icosphere(4).V.rows();
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const AggregatedOperators& level = levels[k];
    const LaplaceOperators& finer = k == 0 ? ops : levels[k - 1].coarse;
    SCOPED_TRACE("level " + std::to_string(k));
    EXPECT_LT(level.coarseSize(), finer.mass.size() / 4);
    EXPECT_GE(level.coarseSize(), 100);
    EXPECT_EQ(level.prolongation.rows(), finer.mass.size());
    EXPECT_EQ(level.prolongation.cols(), level.coarseSize());
    EXPECT_NEAR(level.coarse.mass.sum(), ops.mass.sum(), 1e-12 * ops.mass.sum());
    EXPECT_GT(level.coarse.mass.minCoeff(), 0.0);
    // P·1 = 1: constants are prolonged exactly, so S_c·1 = PᵀS·1 = 0 (one zero eigenvalue per component)
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(level.coarseSize());
    EXPECT_LT((level.prolongation * ones - Eigen::VectorXd::Ones(finer.mass.size())).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((level.coarse.stiffness * ones).cwiseAbs().maxCoeff(),
              1e-9 * level.coarse.stiffness.diagonal().maxCoeff());
    const SparseMatrix asymmetry = level.coarse.stiffness - SparseMatrix(level.coarse.stiffness.transpose());
    EXPECT_LT(asymmetry.cwiseAbs().sum(), 1e-12 * level.coarse.stiffness.cwiseAbs().sum());
    // the Galerkin identities: S_c = PᵀSP and mass_c = Pᵀmass
    const SparseMatrix galerkin =
        SparseMatrix(level.prolongation.transpose()) * finer.stiffness * level.prolongation - level.coarse.stiffness;
    EXPECT_LT(galerkin.cwiseAbs().sum(), 1e-12 * level.coarse.stiffness.cwiseAbs().sum());
    EXPECT_LT((level.prolongation.transpose() * finer.mass - level.coarse.mass).cwiseAbs().maxCoeff(),
              1e-12 * ops.mass.sum());
  }
  // no aggregate spans two components, and no column of P reaches into another component: the mesh's vertex
  // ranges [0, a), [a, 2a), [2a, #V) are the components; follow every level's P down to the mesh
  SparseMatrix toMesh = levels[0].prolongation;
  for (std::size_t k = 1; k < levels.size(); ++k) toMesh = toMesh * levels[k].prolongation;
  std::vector<int> owner(static_cast<std::size_t>(toMesh.cols()), -1);
  int crossings = 0;
  for (Eigen::Index j = 0; j < toMesh.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(toMesh, j); it; ++it) {
      const int c = it.row() < a ? 0 : (it.row() < 2 * a ? 1 : 2);
      int& o = owner[static_cast<std::size_t>(j)];
      if (o < 0) o = c;
      crossings += o != c ? 1 : 0;
    }
  EXPECT_EQ(crossings, 0);
  EXPECT_EQ(levels[0].aggregate.size(), ops.mass.size());
  EXPECT_EQ(levels[0].aggregate.maxCoeff() + 1, levels[0].coarseSize());
}

}  // namespace
}  // namespace sc::spectral
