// SubtreeLdltSolve: solves with a CHOLMOD simplicial LDLᵀ factor split over threads along its elimination tree,
// against CHOLMOD's own solve on the same factor.

#include "spectral/subtree_ldlt_solve.h"
#include "spectral/laplace_operators.h"
#include "spectral/shift_invert_operator.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <numbers>
#include <numeric>

namespace sc::spectral::detail {
namespace {

/// S − σM factored by CHOLMOD's simplicial LDLᵀ (InertiaLdlt, as ShiftInvertOperator does).
struct Factored {
  LaplaceOperators ops;
  InertiaLdlt ldlt;
  Factored(const testing::GeneratedMesh& mesh, double sigmaTimesArea) : ops(laplaceOperators(mesh.V, mesh.F)) {
    SparseMatrix shifted = ops.stiffness;
    shifted.diagonal() -= sigmaTimesArea / ops.totalArea * ops.mass;
    ldlt.compute(shifted);
  }
};

void expectSolvesLikeCholmod(const InertiaLdlt& ldlt, Eigen::Index n, const char* what) {
  for (const int threads : {1, 2, 3, 5}) {
    const std::optional<SubtreeLdltSolve> solver = SubtreeLdltSolve::split(ldlt.factor(), threads);
    ASSERT_TRUE(solver.has_value()) << what;
    EXPECT_EQ(solver->threads(), threads);
    for (const int columns : {1, 3, 4, 6, 9}) {
      const Eigen::MatrixXd x = Eigen::MatrixXd::Random(n, columns);
      Eigen::MatrixXd expected, solved;
      ldlt.solveColumnsInOrder(x, expected, 1);
      solver->solve(x, solved);
      ASSERT_EQ(solved.rows(), n);
      ASSERT_EQ(solved.cols(), columns);
      EXPECT_LE((solved - expected).norm(), 1e-12 * expected.norm())
          << what << ", " << threads << " threads, " << columns << " columns";
    }
  }
}

TEST(SubtreeLdltSolve, SolvesLikeCholmodOnAConnectedMeshBelowAndInsideTheSpectrum) {
  const auto mesh = testing::torus(64, 24);
  const Factored below(mesh, -4.0 * std::numbers::pi);
  ASSERT_EQ(below.ldlt.info(), Eigen::Success);
  expectSolvesLikeCholmod(below.ldlt, below.ops.mass.size(), "sigma below the spectrum");
  const Factored inside(mesh, 300.0);  // about the 50th eigenvalue of a torus of area ~12: D has negative entries
  ASSERT_EQ(inside.ldlt.info(), Eigen::Success);
  ASSERT_GT(inside.ldlt.negativePivots(), 0);
  expectSolvesLikeCholmod(inside.ldlt, inside.ops.mass.size(), "sigma inside the spectrum");
}

TEST(SubtreeLdltSolve, SolvesLikeCholmodOnAForestOfComponents) {
  const Factored forest(testing::twoSpheresAndATorus(), -4.0 * std::numbers::pi);
  ASSERT_EQ(forest.ldlt.info(), Eigen::Success);
  expectSolvesLikeCholmod(forest.ldlt, forest.ops.mass.size(), "three components");
}

TEST(SubtreeLdltSolve, CutsAConnectedMeshSoThatTheLongestSweepIsWellUnderTheWhole) {
  const Factored factored(testing::icosphere(5), -4.0 * std::numbers::pi);
  const cholmod_factor& factor = factored.ldlt.factor();
  const auto* counts = static_cast<const int*>(factor.nz);
  const std::int64_t total = std::accumulate(counts, counts + factor.n, std::int64_t{0});
  for (const int threads : {1, 2, 4}) {
    const std::optional<SubtreeLdltSolve> solver = SubtreeLdltSolve::split(factor, threads);
    ASSERT_TRUE(solver.has_value());
    const std::vector<std::int64_t> entries = solver->sweptEntries();
    ASSERT_EQ(entries.size(), static_cast<std::size_t>(threads) + 1);
    EXPECT_EQ(std::accumulate(entries.begin(), entries.end(), std::int64_t{0}), total) << "every entry swept once";
    const std::int64_t top = entries.back();
    const std::int64_t share = *std::max_element(entries.begin(), entries.end() - 1);
    EXPECT_EQ(top > 0, threads > 1) << "one tree is cut only for several threads";
    // the longest sweep (a thread's subtrees, then the top): 0.61 and 0.47 of L here (2 and 4 threads)
    const double longest = static_cast<double>(share + top) / static_cast<double>(total);
    EXPECT_LE(longest, threads == 1 ? 1.0 : threads == 2 ? 0.65 : 0.5) << threads << " threads";
  }
}

/// A supernodal factor, whose columns the sweeps cannot read.
struct SupernodalLlt : Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> {
  const cholmod_factor& factor() const { return *m_cholmodFactor; }
};

TEST(SubtreeLdltSolve, DeclinesAFactorItCannotSweep) {
  const auto mesh = testing::icosphere(3);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  SparseMatrix shifted = ops.stiffness;
  shifted.diagonal() += ops.mass;
  SupernodalLlt llt;
  llt.compute(shifted);
  ASSERT_EQ(llt.info(), Eigen::Success);
  EXPECT_FALSE(SubtreeLdltSolve::split(llt.factor(), 2).has_value());
}

}  // namespace
}  // namespace sc::spectral::detail
