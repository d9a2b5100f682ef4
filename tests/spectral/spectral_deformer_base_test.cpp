// SpectralDeformer from a base shape (issue 15, "edits that accumulate"): a new constraint set acts from the current
// shape, so identity poses change nothing, anchors hold where they are now and handles move from where they are now.

#include "spectral/spectral_deformer.h"

#include "spectral/spectral_transform.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <limits>
#include <vector>

namespace sc::spectral {
namespace {

struct Bar {
  Bar() : V(testing::torus(60, 20).V), F(testing::torus(60, 20).F) {
    ops = laplaceOperators(V, F);
    BasisOptions options;
    options.m = 60;
    const BasisResult r = manifoldHarmonicBasis(ops, options);
    EXPECT_TRUE(r.ok()) << r.message;
    basis = r.basis;
  }
  /// Vertices within `radius` of (x, y, 0) (the torus lies around the z axis, major radius ≈ 1).
  std::vector<int> near(double x, double y, double radius) const {
    std::vector<int> out;
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      if ((V.row(i).transpose() - Eigen::Vector3d(x, y, 0.0)).norm() < radius) out.push_back(static_cast<int>(i));
    return out;
  }
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  LaplaceOperators ops;
  HarmonicBasis basis;
};

HandleTransform moved(double x, double y, double z, double angle = 0.0) {
  HandleTransform T;
  T.translation = {x, y, z};
  T.rotation = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

/// The shape of A's edit: handle at +x raised in z, anchors at −x.
Eigen::MatrixXd firstEdit(const Bar& bar, SpectralDeformer& deformer) {
  EXPECT_TRUE(deformer.setConstraints({{{bar.near(1.3, 0.0, 0.35)}}, bar.near(-1.3, 0.0, 0.35)}));
  const HandleTransform up[] = {moved(0.0, 0.0, 0.4)};
  return deformer.solve(up);
}

TEST(SpectralDeformerBase, IdentityPosesFromANewBaseLeaveTheShapeExactlyAsItWasInBothModes) {
  const Bar bar;
  for (DeformationMode mode : {DeformationMode::Linear, DeformationMode::Rigid}) {
    DeformerOptions options;
    options.mode = mode;
    SpectralDeformer deformer(bar.basis, bar.ops, bar.V, options);
    const Eigen::MatrixXd shape = firstEdit(bar, deformer);
    ASSERT_GT(shape.cwiseAbs().maxCoeff(), 1e-3);
    // B takes over with a different handle and anchors, starting from A's shape.
    ASSERT_TRUE(deformer.setConstraints({{{bar.near(0.0, 1.3, 0.35)}}, bar.near(1.3, 0.0, 0.35)}, shape));
    EXPECT_EQ(deformer.coefficients(), shape);
    const HandleTransform still[] = {HandleTransform{}};
    const Eigen::MatrixXd Z = deformer.solve(still);
    if (mode == DeformationMode::Linear) {
      EXPECT_LT((Z - shape).cwiseAbs().maxCoeff(), 1e-12 * shape.cwiseAbs().maxCoeff());
    } else {
      // ARAP relaxes the free parts towards rigid pieces, but the constrained vertices hold where they were.
      EXPECT_LT(deformer.residual(still).maxAnchor, 0.02);
    }
  }
}

TEST(SpectralDeformerBase, ATranslationFromABaseAddsExactlyWhatTheSameDragAddsFromRestInLinearMode) {
  const Bar bar;
  SpectralDeformer deformer(bar.basis, bar.ops, bar.V);
  const Eigen::MatrixXd shape = firstEdit(bar, deformer);
  const ConstraintSet second{{{bar.near(0.0, 1.3, 0.35)}}, bar.near(-1.3, 0.0, 0.35)};
  const HandleTransform drag[] = {moved(0.0, 0.3, 0.0)};

  SpectralDeformer fromRest(bar.basis, bar.ops, bar.V);
  ASSERT_TRUE(fromRest.setConstraints(second));
  const Eigen::MatrixXd alone = fromRest.solve(drag);

  ASSERT_TRUE(deformer.setConstraints(second, shape));
  const Eigen::MatrixXd together = deformer.solve(drag);
  EXPECT_LT((together - (shape + alone)).cwiseAbs().maxCoeff(), 1e-12 * alone.cwiseAbs().maxCoeff());
}

TEST(SpectralDeformerBase, AnchorsHoldAndTheHandleMovesFromWhereItIsNowNotFromRest) {
  const Bar bar;
  SpectralDeformer deformer(bar.basis, bar.ops, bar.V);
  const Eigen::MatrixXd shape = firstEdit(bar, deformer);
  const std::vector<int> raised = bar.near(1.3, 0.0, 0.35);
  const std::vector<int> middle = bar.near(0.0, 1.3, 0.35);
  // the raised end is now an anchor: it stays raised while the side between them moves.
  ASSERT_TRUE(deformer.setConstraints({{{middle}}, raised}, shape));
  const HandleTransform drag[] = {moved(0.0, 0.25, 0.0, 0.2)};
  const Eigen::MatrixXd Z = deformer.solve(drag);
  const Eigen::MatrixXd before = reconstruct(bar.V, bar.basis.vectors, shape);
  const Eigen::MatrixXd after = reconstruct(bar.V, bar.basis.vectors, Z);
  double raisedHeight = 0.0;
  for (int v : raised) raisedHeight += after(v, 2) - bar.V(v, 2);
  raisedHeight /= static_cast<double>(raised.size());
  EXPECT_GT(raisedHeight, 0.3) << "A's raised end snapped back";
  const ConstraintResidual r = deformer.residual(drag);
  EXPECT_LT(r.maxAnchor, 0.05);
  EXPECT_LT(r.rmsHandle, 0.05);
  // the handle's target is about its centroid in the current shape
  Eigen::Vector3d centroidBefore = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroidAfter = Eigen::Vector3d::Zero();
  for (int v : middle) {
    centroidBefore += before.row(v).transpose();
    centroidAfter += after.row(v).transpose();
  }
  centroidBefore /= static_cast<double>(middle.size());
  centroidAfter /= static_cast<double>(middle.size());
  EXPECT_NEAR((centroidAfter - centroidBefore).y(), 0.25, 0.03);
}

TEST(SpectralDeformerBase, RebaseRefusesAWrongSizeOrNonFiniteBaseAndKeepsTheOldOne) {
  const Bar bar;
  SpectralDeformer deformer(bar.basis, bar.ops, bar.V);
  const Eigen::MatrixXd shape = firstEdit(bar, deformer);
  ASSERT_TRUE(deformer.rebase(shape));
  EXPECT_FALSE(deformer.rebase(Eigen::MatrixXd::Zero(shape.rows() + 1, 3)));
  Eigen::MatrixXd bad = shape;
  bad(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(deformer.rebase(bad));
  EXPECT_FALSE(deformer.setConstraints({{{bar.near(0.0, 1.3, 0.35)}}, {}}, bad));
  EXPECT_EQ(deformer.base(), shape);
  EXPECT_EQ(deformer.coefficients(), shape);
}

TEST(SpectralDeformerChange, TwoGroupsPosesTogetherAreTheSumOfEachAloneFromTheBaseInLinearMode) {
  const Bar bar;
  SpectralDeformer deformer(bar.basis, bar.ops, bar.V);
  const Eigen::MatrixXd shape = firstEdit(bar, deformer);
  // two people's handles, one solve: +y side and −y side, anchors at −x
  ASSERT_TRUE(deformer.setConstraints(
      {{{bar.near(0.0, 1.3, 0.35)}, {bar.near(0.0, -1.3, 0.35)}}, bar.near(-1.3, 0.0, 0.35)}, shape));
  const HandleTransform both[] = {moved(0.0, 0.3, 0.1, 0.2), moved(0.1, -0.2, 0.0)};
  const HandleTransform first[] = {both[0], HandleTransform{}};
  const HandleTransform second[] = {HandleTransform{}, both[1]};
  const Eigen::MatrixXd a = deformer.change(first);
  const Eigen::MatrixXd b = deformer.change(second);
  ASSERT_GT(a.cwiseAbs().maxCoeff(), 1e-3);
  ASSERT_GT(b.cwiseAbs().maxCoeff(), 1e-3);
  const Eigen::MatrixXd Z = deformer.solve(both);
  EXPECT_LT((Z - (shape + a + b)).cwiseAbs().maxCoeff(), 1e-12 * Z.cwiseAbs().maxCoeff());
  EXPECT_EQ(deformer.change(std::vector<HandleTransform>{}).cwiseAbs().maxCoeff(), 0.0);
  HandleTransform far = moved(1e9, 0.0, 0.0);
  const HandleTransform outOfRange[] = {far};
  EXPECT_EQ(deformer.change(outOfRange).cwiseAbs().maxCoeff(), 0.0) << "a pose out of range changes nothing";
}

}  // namespace
}  // namespace sc::spectral
