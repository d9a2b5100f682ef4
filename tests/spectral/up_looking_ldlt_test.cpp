// factorUpLooking: the numeric LDLᵀ factorisation of S − σM into CHOLMOD's simplicial analysis, its rows split over
// threads along the elimination tree, against cholmod_factorize on the same analysis.

#include "spectral/up_looking_ldlt.h"
#include "spectral/laplace_operators.h"
#include "spectral/shift_invert_operator.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>

#include <cmath>
#include <numbers>

namespace sc::spectral::detail {
namespace {

SparseMatrix shiftedStiffness(const testing::GeneratedMesh& mesh, double sigmaTimesArea) {
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  SparseMatrix shifted = ops.stiffness;
  shifted.diagonal() -= sigmaTimesArea / ops.totalArea * ops.mass;
  return shifted;
}

/// Column j of a simplicial factor: its row indices and values (D first).
struct Column {
  std::vector<int> rows;
  std::vector<double> values;
};

Column column(const cholmod_factor& factor, int j) {
  const auto* starts = static_cast<const int*>(factor.p);
  const auto* counts = static_cast<const int*>(factor.nz);
  const auto* rows = static_cast<const int*>(factor.i);
  const auto* values = static_cast<const double*>(factor.x);
  return {{rows + starts[j], rows + starts[j] + counts[j]}, {values + starts[j], values + starts[j] + counts[j]}};
}

/// The same pattern as CHOLMOD's factor, entries equal to `tolerance` relative to the column's largest (they differ by
/// rounding: CHOLMOD sums each row's updates in another order), and the same bits on every thread count (the rows
/// reach each column in the same order).
void expectFactorsLikeCholmod(const SparseMatrix& shifted, double tolerance, const char* what) {
  InertiaLdlt cholmod;
  cholmod.compute(shifted);
  ASSERT_EQ(cholmod.info(), Eigen::Success) << what;
  const cholmod_factor& expected = cholmod.factor();
  const auto n = static_cast<int>(expected.n);
  std::vector<Column> firstColumns;
  for (const int threads : {1, 2, 3, 5}) {
    InertiaLdlt ldlt;
    ldlt.analyzePattern(shifted);
    ldlt.factorizeOnThreads(shifted, threads);
    ASSERT_EQ(ldlt.info(), Eigen::Success) << what;
    const cholmod_factor& factor = ldlt.factor();
    ASSERT_EQ(factor.minor, factor.n);
    ASSERT_EQ(factor.is_ll, 0);
    ASSERT_EQ(factor.is_monotonic, 1);
    for (int j = 0; j < n; ++j) {
      const Column mine = column(factor, j);
      const Column theirs = column(expected, j);
      ASSERT_EQ(mine.rows, theirs.rows) << what << ", column " << j << ", " << threads << " threads";
      double largest = 0.0;
      for (const double value : theirs.values) largest = std::max(largest, std::abs(value));
      for (std::size_t p = 0; p < mine.values.size(); ++p)
        ASSERT_NEAR(mine.values[p], theirs.values[p], tolerance * largest) << what << ", column " << j;
      if (threads == 1)
        firstColumns.push_back(mine);
      else
        ASSERT_EQ(mine.values, firstColumns[static_cast<std::size_t>(j)].values)
            << what << ": " << threads << " threads changed column " << j;
    }
    EXPECT_EQ(ldlt.negativePivots(), cholmod.negativePivots()) << what;
    const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd x = ldlt.solve(b);
    EXPECT_LE((shifted * x - b).norm(), 1e-9 * b.norm()) << what;
  }
}

TEST(UpLookingLdlt, FactorsLikeCholmodBelowAndInsideTheSpectrum) {
  const auto mesh = testing::torus(64, 24);
  expectFactorsLikeCholmod(shiftedStiffness(mesh, -4.0 * std::numbers::pi), 1e-12, "sigma below the spectrum");
  // about the 50th eigenvalue of a torus of area ~12: D has negative entries
  const SparseMatrix inside = shiftedStiffness(mesh, 300.0);
  InertiaLdlt ldlt;
  ldlt.analyzePattern(inside);
  ldlt.factorizeOnThreads(inside, 2);
  ASSERT_GT(ldlt.negativePivots(), 0);
  // indefinite, without pivoting: small pivots amplify the rounding (1.3e-12 of a column's largest entry measured)
  expectFactorsLikeCholmod(inside, 1e-10, "sigma inside the spectrum");
}

TEST(UpLookingLdlt, FactorsLikeCholmodOnAForestOfComponents) {
  expectFactorsLikeCholmod(shiftedStiffness(testing::twoSpheresAndATorus(), -4.0 * std::numbers::pi), 1e-12,
                           "three components");
}

TEST(UpLookingLdlt, RefactorsWithANewShiftOnTheSameAnalysis) {
  const auto mesh = testing::icosphere(3);
  InertiaLdlt ldlt;
  const SparseMatrix first = shiftedStiffness(mesh, -4.0 * std::numbers::pi);
  ldlt.analyzePattern(first);
  ldlt.factorizeOnThreads(first, 2);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const SparseMatrix second = shiftedStiffness(mesh, 50.0);
  ldlt.factorizeOnThreads(second, 2);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  InertiaLdlt cholmod;
  cholmod.compute(second);
  EXPECT_EQ(ldlt.negativePivots(), cholmod.negativePivots());
  const Eigen::VectorXd b = Eigen::VectorXd::Random(second.rows());
  EXPECT_LE((ldlt.solve(b) - cholmod.solve(b)).norm(), 1e-10 * cholmod.solve(b).norm());
}

TEST(UpLookingLdlt, AZeroPivotIsReportedAsAFailedFactorisation) {
  SparseMatrix a(4, 4);
  a.insert(0, 0) = 2.0;
  a.insert(1, 1) = 0.0;  // stored, exactly zero: D has a zero whatever the order
  a.insert(2, 2) = 3.0;
  a.insert(3, 3) = 1.0;
  a.insert(3, 0) = 1.0;
  a.insert(0, 3) = 1.0;
  a.makeCompressed();
  InertiaLdlt ldlt;
  ldlt.analyzePattern(a);
  ldlt.factorizeOnThreads(a, 2);
  EXPECT_EQ(ldlt.info(), Eigen::NumericalIssue);
  EXPECT_LT(ldlt.factor().minor, ldlt.factor().n);
}

TEST(UpLookingLdlt, DeclinesASupernodalAnalysis) {
  const SparseMatrix shifted = shiftedStiffness(testing::icosphere(2), -4.0 * std::numbers::pi);
  cholmod_common common;
  cholmod_start(&common);
  common.supernodal = CHOLMOD_SUPERNODAL;
  SparseMatrix lower = shifted.triangularView<Eigen::Lower>();
  cholmod_sparse view = Eigen::viewAsCholmod(lower);
  view.stype = -1;
  cholmod_factor* factor = cholmod_analyze(&view, &common);
  ASSERT_NE(factor, nullptr);
  ASSERT_NE(factor->is_super, 0);
  EXPECT_FALSE(factorUpLooking(shifted, *factor, 2, common));
  EXPECT_EQ(factor->xtype, CHOLMOD_PATTERN) << "left as it was";
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
}

}  // namespace
}  // namespace sc::spectral::detail
