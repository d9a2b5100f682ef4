// The fast eigensolvers (hierarchical subspace iteration, spectrum slicing) against the Lanczos reference, each test
// run for both.
//
// Tolerances follow from the residual bounds for S h = λ M h (Parlett, subspace_iteration.h): with r_k the
// M⁻¹-norm residual of an M-normalised Ritz pair and δ the gap from a cluster of eigenvalues to the rest of the
// spectrum, |θ_k − λ_k| ≤ r_k²/δ and the sine of the largest principal angle between the cluster's Ritz vectors and
// its eigenspace is ≤ ‖[r_k]‖_F/δ. The tests compute these bounds from the returned residuals (plus a slack for the
// reference's own error) instead of fixed numbers, and compare subspaces per cluster, never single vectors.

#include "spectral/harmonic_basis.h"
#include "spectral/spectral_deformer.h"
#include "spectral/spectral_transform.h"
#include "spectral/subspace_iteration.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <string>

namespace sc::spectral {
namespace {

/// Both fast solvers on meshes of test size: slicing is forced below its usual size threshold, with 3 slices so that
/// hand-overs fall between multiplets.
BasisResult solve(const LaplaceOperators& ops, int m, BasisSolver solver) {
  BasisOptions options;
  options.m = m;
  options.solver = solver;
  options.sliceMinimumVertices = 0;
  options.slices = 3;
  return manifoldHarmonicBasis(ops, options);
}

/// The largest m ≤ atMost that ends a cluster of `lambda` (relative gap above it > clusterGap): comparing a basis
/// cut inside a (near-)degenerate cluster would compare arbitrary choices.
int mAtClusterEnd(const Eigen::VectorXd& lambda, int atMost, double clusterGap, double sigma) {
  int m = atMost;
  while (m > 1 && lambda(m) - lambda(m - 1) <= clusterGap * (lambda(m) + std::abs(sigma))) --m;
  return m;
}

/// Compares a fast solver's basis with Lanczos cluster by cluster. `reference` has more pairs than `fast`, so the
/// gap above the last compared cluster is known. Clusters: consecutive reference eigenvalues closer than
/// `clusterGap`·(λ + |σ|) (a relative threshold: discrete spheres split the 2l+1 multiplets slightly).
void expectSameEigenpairs(const LaplaceOperators& ops, const HarmonicBasis& fast, const HarmonicBasis& reference,
                          double clusterGap) {
  const Eigen::Index m = fast.size();
  ASSERT_GT(reference.size(), m);
  const Eigen::VectorXd r =
      detail::relativeResiduals(ops.stiffness * fast.vectors, ops.mass.asDiagonal() * fast.vectors, ops.mass,
                                fast.eigenvalues, fast.shift)
          .cwiseProduct((fast.eigenvalues.cwiseAbs().array() + std::abs(fast.shift)).matrix());
  const Eigen::VectorXd& lambda = reference.eigenvalues;
  const double slack = 1e-9 * (lambda(m) + std::abs(fast.shift));  // the reference's own error (tolerance 1e-10)
  int clusters = 0;
  for (Eigen::Index first = 0; first < m;) {
    Eigen::Index size = 1;
    while (first + size < reference.size() && lambda(first + size) - lambda(first + size - 1) <=
                                                  clusterGap * (lambda(first + size) + std::abs(fast.shift)))
      ++size;
    const Eigen::Index last = first + size;  // one past
    ASSERT_LE(last, m) << "m must end a cluster";
    const double below = first > 0 ? lambda(first) - lambda(first - 1) : 1e300;
    const double gap = std::min(below, lambda(last) - lambda(last - 1));
    const double residualNorm = r.segment(first, size).norm();
    SCOPED_TRACE("cluster " + std::to_string(first) + ".." + std::to_string(last - 1) + " gap " + std::to_string(gap));
    for (Eigen::Index k = first; k < last; ++k)
      EXPECT_NEAR(fast.eigenvalues(k), lambda(k), std::pow(r(k), 2) / gap + (lambda(last - 1) - lambda(first)) + slack);
    // the largest principal angle's sine, measured directly: the M-norm of what is left of the fast cluster's
    // vectors H_f after the reference cluster's M-orthogonal projection, σ_max(M^½ (H_f − H_r H_rᵀ M H_f)). Taken
    // as √(1 − cos²) it could not go below √(2·(1 − cos)), about 10⁻⁶ for columns M-orthonormal to 10⁻¹².
    const auto fastCluster = fast.vectors.middleCols(first, size);
    const auto referenceCluster = reference.vectors.middleCols(first, size);
    const Eigen::MatrixXd left =
        fastCluster - referenceCluster * (referenceCluster.transpose() * (ops.mass.asDiagonal() * fastCluster));
    const Eigen::MatrixXd leftGram = left.transpose() * (ops.mass.asDiagonal() * left);
    const double sine =
        std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(leftGram).eigenvalues().maxCoeff()));
    // Davis–Kahan (M-inner product, residuals in the M⁻¹-norm): sine ≤ ‖R‖/gap; the slack covers both bases'
    // M-orthonormality errors (up to 1e-10 for the fast one).
    EXPECT_LE(sine, residualNorm / gap + 1e-9) << "largest principal angle's sine";
    ++clusters;
    first = last;
  }
  EXPECT_GT(clusters, 1);
}

class FastEigensolver : public ::testing::TestWithParam<BasisSolver> {};

/// The solver asked for ran, or (spectrum slicing only) its checks found a slice that missed a copy of a multiple
/// eigenvalue (meshes with exact symmetries) and the hierarchical solver ran instead, saying why. Either way the
/// basis is compared.
void expectSolverOrItsReportedFallback(const BasisResult& r, BasisSolver asked) {
  if (asked == BasisSolver::Slices && r.solver != BasisSolver::Slices) {
    EXPECT_EQ(r.solver, BasisSolver::Hierarchical);
    EXPECT_NE(r.message.find("spectrum slicing fell back to the hierarchical solver"), std::string::npos) << r.message;
    return;
  }
  EXPECT_EQ(r.solver, asked) << r.message;
}

TEST_P(FastEigensolver, SphereMatchesLanczosPerMultiplet) {
  // λ ≈ l(l+1), multiplicity 2l+1: m = 36 ends the l = 5 multiplet.
  const auto mesh = testing::icosphere(5);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const BasisResult fast = solve(ops, 36, GetParam());
  ASSERT_TRUE(fast.ok()) << fast.message;
  expectSolverOrItsReportedFallback(fast, GetParam());
  const BasisResult reference = solve(ops, 40, BasisSolver::Lanczos);
  ASSERT_TRUE(reference.ok()) << reference.message;
  expectSameEigenpairs(ops, fast.basis, reference.basis, 0.05);
  EXPECT_LE(fast.maxResidual, BasisOptions{}.residualTolerance);
  EXPECT_LE(orthonormalityError(fast.basis.vectors, ops.mass), 1e-10);
}

TEST_P(FastEigensolver, ThreeComponentsWithEqualSpheresMatchLanczos) {
  const auto mesh = testing::twoSpheresAndATorus();
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const BasisResult reference = solve(ops, 44, BasisSolver::Lanczos);
  ASSERT_TRUE(reference.ok()) << reference.message;
  const int m = mAtClusterEnd(reference.basis.eigenvalues, 30, 0.02, reference.basis.shift);
  ASSERT_GE(m, 20);
  const BasisResult fast = solve(ops, m, GetParam());
  ASSERT_TRUE(fast.ok()) << fast.message;
  expectSolverOrItsReportedFallback(fast, GetParam());
  // three zero eigenvalues, one per component
  EXPECT_NEAR(fast.basis.eigenvalues(2), 0.0, 1e-8);
  EXPECT_GT(fast.basis.eigenvalues(3), 1e-3);
  expectSameEigenpairs(ops, fast.basis, reference.basis, 0.02);
  EXPECT_LE(fast.maxResidual, BasisOptions{}.residualTolerance);
  EXPECT_LE(orthonormalityError(fast.basis.vectors, ops.mass), 1e-10);
  // localised: every vector lives on one component (else dragging one sphere would move the other)
  const Eigen::Index a = testing::icosphere(4).V.rows();
  for (Eigen::Index k = 0; k < fast.basis.size(); ++k) {
    const Eigen::VectorXd h2 = fast.basis.vectors.col(k).cwiseAbs2().cwiseProduct(ops.mass);
    const double share = std::max({h2.head(a).sum(), h2.segment(a, a).sum(), h2.tail(h2.size() - 2 * a).sum()});
    EXPECT_GT(share, 1.0 - 1e-10) << "column " << k;
  }
}

TEST_P(FastEigensolver, DeformationAgreesWithLanczosBasis) {
  // Bending a bar: same constraints and drag with either basis; the shapes agree to far below what is visible.
  // m ends a cluster: the tube's rotational symmetry makes most eigenvalues double.
  const auto mesh = testing::tube(40, 160);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  const BasisResult probe = solve(ops, 70, BasisSolver::Lanczos);
  ASSERT_TRUE(probe.ok()) << probe.message;
  const int m = mAtClusterEnd(probe.basis.eigenvalues, 60, 0.01, probe.basis.shift);
  ASSERT_GE(m, 40);
  const BasisResult fast = solve(ops, m, GetParam());
  const BasisResult reference = solve(ops, m, BasisSolver::Lanczos);
  ASSERT_TRUE(fast.ok()) << fast.message;
  ASSERT_TRUE(reference.ok()) << reference.message;
  expectSolverOrItsReportedFallback(fast, GetParam());
  ConstraintSet constraints;
  HandleGroup handle;
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    if (mesh.V(i, 0) > 3.7) handle.vertices.push_back(static_cast<int>(i));
    if (mesh.V(i, 0) < 0.3) constraints.anchors.push_back(static_cast<int>(i));
  }
  constraints.handles.push_back(handle);
  HandleTransform drag;
  drag.translation = {0.0, 1.0, 0.2};
  const double diagonal = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  for (DeformationMode mode : {DeformationMode::Linear, DeformationMode::Rigid}) {
    DeformerOptions options;
    options.mode = mode;
    SpectralDeformer a(fast.basis, ops, mesh.V, options);
    SpectralDeformer b(reference.basis, ops, mesh.V, options);
    ASSERT_TRUE(a.setConstraints(constraints));
    ASSERT_TRUE(b.setConstraints(constraints));
    const HandleTransform poses[] = {drag};
    const Eigen::MatrixXd Xa = reconstruct(mesh.V, fast.basis.vectors, a.solve(poses));
    const Eigen::MatrixXd Xb = reconstruct(mesh.V, reference.basis.vectors, b.solve(poses));
    const double moved = (Xb - mesh.V).rowwise().norm().maxCoeff();
    EXPECT_GT(moved, 0.1 * diagonal) << "the drag must bend the bar";
    // Linear: Z solves an m×m system in the basis, so the shapes differ by about the subspace angle (≤ 1e-6 here)
    // times the displacement. Rigid: the rotation clusters come from k-means on the basis rows, a discrete choice
    // that a 1e-6 change of the basis can flip for a vertex on a cluster border: a looser bound.
    const double tolerance = mode == DeformationMode::Linear ? 1e-5 : 1e-3;
    EXPECT_LT((Xa - Xb).rowwise().norm().maxCoeff(), tolerance * diagonal) << "mode " << static_cast<int>(mode);
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, FastEigensolver, ::testing::Values(BasisSolver::Hierarchical, BasisSolver::Slices),
                         [](const ::testing::TestParamInfo<BasisSolver>& solver) { return toString(solver.param); });

}  // namespace
}  // namespace sc::spectral
