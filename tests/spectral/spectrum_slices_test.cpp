// Spectrum slicing's own rules: the inertia count that places each slice, the merge of overlapping slices and what
// it refuses, fallback, cancellation and threads. Its eigenpairs against the Lanczos reference:
// fast_eigensolvers_test.cpp.

#include "spectral/spectrum_slices.h"
#include "spectral/harmonic_basis.h"
#include "spectral/shift_invert_operator.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace sc::spectral {
namespace {

using detail::SpectrumSlice;

BasisOptions slicing(int m, int slices, int threads) {
  BasisOptions options;
  options.m = m;
  options.solver = BasisSolver::Slices;
  options.sliceMinimumVertices = 0;
  options.slices = slices;
  options.sliceThreads = threads;
  return options;
}

/// A slice over `values` (ascending) starting at index `first`, whose column k is the unit vector e_(first + k) of
/// R^rows, so that the merged columns show which index they came from; `tag` is added to every entry of the slice's
/// columns to show which slice.
SpectrumSlice syntheticSlice(int first, const std::vector<double>& values, Eigen::Index rows, double tag) {
  SpectrumSlice slice;
  slice.first = first;
  slice.eigenvalues = Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  slice.vectors = Eigen::MatrixXd::Constant(rows, slice.eigenvalues.size(), tag);
  for (Eigen::Index k = 0; k < slice.eigenvalues.size(); ++k) slice.vectors(first + k, k) += 1.0;
  return slice;
}

TEST(SpectrumSlices, InertiaCountsTheEigenvaluesBelowTheShift) {
  const auto mesh = testing::torus(48, 16);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions options;
  options.m = 40;
  const BasisResult reference = manifoldHarmonicBasis(ops, options);
  ASSERT_TRUE(reference.ok()) << reference.message;
  const Eigen::VectorXd& lambda = reference.basis.eigenvalues;
  int checked = 0;
  for (int below = 1; below < 40; ++below) {
    if (lambda(below) - lambda(below - 1) < 1e-6 * lambda(below)) continue;  // inside a multiplet: no shift between
    detail::ShiftInvertOperator op(ops.stiffness, ops.mass, {});
    op.set_shift(0.5 * (lambda(below - 1) + lambda(below)));
    EXPECT_EQ(op.eigenvaluesBelowShift(), below);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(SpectrumSlices, MergeHandsOverAtTheWidestGapOfTheOverlap) {
  // indices 0..5 from the first slice, 3..9 from the second: the hand-over candidates are 3..6, and the widest
  // relative gap (λ_s − λ_{s−1})/(|λ_s| + 1) among them is the one below index 5 (3 → 4.5)
  const std::vector<SpectrumSlice> slices{syntheticSlice(3, {2.5, 3, 4.5, 5, 6, 7, 8}, 12, 0.5),
                                          syntheticSlice(0, {0, 1, 2, 2.5, 3, 4.5}, 12, 0.25)};
  const detail::MergedSlices merged = detail::mergeSlices(slices, 10, 1.0, 1e-9, 1e-3);
  ASSERT_TRUE(merged.error.empty()) << merged.error;
  EXPECT_EQ(merged.handOvers, std::vector<int>{5});
  const Eigen::VectorXd expected{{0, 1, 2, 2.5, 3, 4.5, 5, 6, 7, 8}};
  EXPECT_EQ(merged.eigenvalues, expected);
  for (Eigen::Index k = 0; k < 10; ++k) {
    EXPECT_EQ(merged.vectors(k, k), k < 5 ? 1.25 : 1.5) << "column " << k;
    EXPECT_EQ(merged.vectors(11, k), k < 5 ? 0.25 : 0.5) << "column " << k;
  }
}

TEST(SpectrumSlices, MergeRefusesSlicesThatDisagreeOnAnIndex) {
  // the second run missed eigenvalue 4 below its shift, so each value it places at index i belongs to i − 1
  const std::vector<SpectrumSlice> slices{syntheticSlice(0, {0, 1, 2, 4, 5, 6.5}, 12, 0),
                                          syntheticSlice(4, {4, 5, 6.5, 7, 8, 9}, 12, 0)};
  const detail::MergedSlices merged = detail::mergeSlices(slices, 10, 1.0, 1e-9, 1e-3);
  EXPECT_NE(merged.error.find("disagree"), std::string::npos) << merged.error;
}

TEST(SpectrumSlices, MergeRefusesIndicesNoSliceCovers) {
  const std::vector<SpectrumSlice> gap{syntheticSlice(0, {0, 1, 2}, 12, 0), syntheticSlice(4, {4, 5, 6, 7}, 12, 0)};
  EXPECT_NE(detail::mergeSlices(gap, 8, 1.0, 1e-9, 1e-3).error.find("covers"), std::string::npos);
  const std::vector<SpectrumSlice> shortTop{syntheticSlice(0, {0, 1, 2, 3}, 12, 0),
                                            syntheticSlice(2, {2, 3, 4, 5}, 12, 0)};
  EXPECT_NE(detail::mergeSlices(shortTop, 8, 1.0, 1e-9, 1e-3).error.find("below m - 1"), std::string::npos);
}

TEST(SpectrumSlices, MergeRefusesAHandOverInsideACluster) {
  // indices 2..6 are one eigenvalue of multiplicity 5 and the overlap 3..4 lies inside it: every hand-over would
  // take part of the eigenspace from one run and part from the other
  const std::vector<SpectrumSlice> slices{syntheticSlice(0, {0, 1, 3, 3, 3}, 12, 0),
                                          syntheticSlice(3, {3, 3, 3, 3, 6}, 12, 0)};
  const detail::MergedSlices merged = detail::mergeSlices(slices, 8, 1.0, 1e-9, 1e-3);
  EXPECT_NE(merged.error.find("no gap"), std::string::npos) << merged.error;
}

/// Two components without symmetries, like a scan with a loose part: a torus and a sphere with jittered vertices.
testing::GeneratedMesh torusAndJitteredSphere() {
  testing::GeneratedMesh sphere = testing::icosphere(4);
  std::srand(7);
  sphere.V = sphere.V * 0.8 + 0.02 * Eigen::MatrixXd::Random(sphere.V.rows(), 3);
  sphere.V.col(0).array() += 4.0;
  return testing::joined(testing::torus(64, 24), sphere);
}

TEST(SpectrumSlices, ManySlicesOnOneThreadAndOnSeveralGiveTheLanczosEigenvalues) {
  const auto mesh = torusAndJitteredSphere();
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions reference;
  reference.m = 60;
  const BasisResult lanczos = manifoldHarmonicBasis(ops, reference);
  ASSERT_TRUE(lanczos.ok()) << lanczos.message;
  for (const auto& [threads, block] : {std::pair{1, true}, std::pair{3, true}, std::pair{3, false}}) {
    BasisOptions options = slicing(60, 5, threads);
    options.blockLanczos = block;  // false: each slice runs Spectra's restarted Lanczos
    const BasisResult sliced = manifoldHarmonicBasis(ops, options);
    ASSERT_TRUE(sliced.ok()) << sliced.message;
    EXPECT_EQ(sliced.solver, BasisSolver::Slices) << sliced.message;
    EXPECT_EQ(sliced.slices, 5);
    const Eigen::VectorXd scale = lanczos.basis.eigenvalues.cwiseAbs().array() + std::abs(lanczos.basis.shift);
    EXPECT_LE((sliced.basis.eigenvalues - lanczos.basis.eigenvalues).cwiseQuotient(scale).cwiseAbs().maxCoeff(), 1e-9)
        << threads << " threads, block Lanczos " << block;
    EXPECT_LE(orthonormalityError(sliced.basis.vectors, ops.mass), 1e-8);
    EXPECT_LE(sliced.maxResidual, 1e-6);
  }
}

TEST(SpectrumSlices, SmallMeshesUseLanczos) {
  const auto mesh = testing::icosphere(3);  // 642 vertices, below the default sliceMinimumVertices
  BasisOptions options;
  options.m = 20;
  options.solver = BasisSolver::Slices;
  const BasisResult r = manifoldHarmonicBasis(laplaceOperators(mesh.V, mesh.F), options);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.solver, BasisSolver::Lanczos);
  EXPECT_EQ(r.slices, 0);
}

TEST(SpectrumSlices, MeshesAboveTheSliceMaximumAreSolvedInOneRunWithTheLanczosEigenvalues) {
  const auto mesh = torusAndJitteredSphere();
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  BasisOptions reference;
  reference.m = 40;
  reference.solver = BasisSolver::Lanczos;
  const BasisResult lanczos = manifoldHarmonicBasis(ops, reference);
  ASSERT_TRUE(lanczos.ok()) << lanczos.message;
  BasisOptions options = slicing(40, 0, 0);
  options.sliceMaximumVertices = ops.mass.size() - 1;  // "too large" for slicing: one block Lanczos run instead
  const BasisResult block = manifoldHarmonicBasis(ops, options);
  ASSERT_TRUE(block.ok()) << block.message;
  EXPECT_EQ(block.solver, BasisSolver::Lanczos);
  EXPECT_EQ(block.slices, 0);
  const Eigen::VectorXd scale = lanczos.basis.eigenvalues.cwiseAbs().array() + std::abs(lanczos.basis.shift);
  EXPECT_LE((block.basis.eigenvalues - lanczos.basis.eigenvalues).cwiseQuotient(scale).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE(orthonormalityError(block.basis.vectors, ops.mass), 1e-8);
  EXPECT_LE(block.maxResidual, 1e-6);
}

TEST(SpectrumSlices, CancelledFromTheProgressCallback) {
  const auto mesh = testing::icosphere(5);
  BasisOptions options = slicing(30, 3, 2);
  options.progress = [](double fraction) { return fraction < 0.3; };
  const BasisResult r = manifoldHarmonicBasis(laplaceOperators(mesh.V, mesh.F), options);
  EXPECT_EQ(r.status, BasisStatus::Cancelled);
  EXPECT_EQ(r.basis.size(), 0);
}

TEST(SpectrumSlices, IndefiniteStiffnessIsAFactorisationFailure) {
  const auto mesh = testing::icosphere(3);
  LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  ops.stiffness = -ops.stiffness;  // every shift below zero now has eigenvalues under it
  const BasisResult r = manifoldHarmonicBasis(ops, slicing(20, 2, 2));
  EXPECT_EQ(r.status, BasisStatus::FactorizationFailed);
}

}  // namespace
}  // namespace sc::spectral
