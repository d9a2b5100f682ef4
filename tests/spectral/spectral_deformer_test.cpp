#include "spectral/spectral_deformer.h"

#include "spectral/spectral_transform.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace sc::spectral {
namespace {

/// A mesh with its operators and basis, kept alive together (the deformer holds references).
struct Scene {
  Scene(testing::GeneratedMesh mesh, int m) : V(std::move(mesh.V)), F(std::move(mesh.F)) {
    ops = laplaceOperators(V, F);
    BasisOptions options;
    options.m = m;
    const BasisResult r = manifoldHarmonicBasis(ops, options);
    EXPECT_TRUE(r.ok()) << r.message;
    basis = r.basis;
    diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  }
  std::vector<int> within(const Eigen::Vector3d& centre, double radius) const {
    std::vector<int> out;
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      if ((V.row(i).transpose() - centre).norm() < radius) out.push_back(static_cast<int>(i));
    return out;
  }
  std::vector<int> where(const std::function<bool(const Eigen::Vector3d&)>& predicate) const {
    std::vector<int> out;
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      if (predicate(V.row(i).transpose())) out.push_back(static_cast<int>(i));
    return out;
  }
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  LaplaceOperators ops;
  HarmonicBasis basis;
  double diagonal = 0.0;
};

HandleTransform translation(double x, double y, double z) {
  HandleTransform T;
  T.translation = {x, y, z};
  return T;
}

TEST(SpectralDeformer, ZeroDragGivesZeroCoefficientsInBothModes) {
  const Scene scene(testing::torus(40, 16), 40);
  for (DeformationMode mode : {DeformationMode::Linear, DeformationMode::Rigid}) {
    DeformerOptions options;
    options.mode = mode;
    SpectralDeformer deformer(scene.basis, scene.ops, scene.V, options);
    ASSERT_TRUE(deformer.setConstraints({{{scene.within({1.3, 0, 0}, 0.3)}}, scene.within({-1.3, 0, 0}, 0.3)}));
    const HandleTransform still[] = {HandleTransform{}};
    EXPECT_LT(deformer.solve(still).cwiseAbs().maxCoeff(), 1e-9) << "mode " << static_cast<int>(mode);
  }
}

TEST(SpectralDeformer, HandlesReachTheirTargetsWithinTheReportedResidualAndAnchorsStay) {
  const Scene scene(testing::torus(60, 20), 80);
  SpectralDeformer deformer(scene.basis, scene.ops, scene.V);
  const std::vector<int> handle = scene.within({1.3, 0, 0}, 0.35);
  const std::vector<int> anchors = scene.where([](const Eigen::Vector3d& x) { return x.x() < -0.5; });
  ASSERT_TRUE(deformer.setConstraints({{{handle}}, anchors}));

  HandleTransform T = translation(0.0, 0.0, 0.3);
  T.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const HandleTransform transforms[] = {T};
  const Eigen::MatrixXd X = reconstruct(scene.V, scene.basis.vectors, deformer.solve(transforms));
  const ConstraintResidual r = deformer.residual(transforms);

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : handle) centroid += scene.V.row(v).transpose();
  centroid /= static_cast<double>(handle.size());
  for (int v : handle) {
    const Eigen::Vector3d target = T.rotation * (scene.V.row(v).transpose() - centroid) + centroid + T.translation;
    EXPECT_LE((X.row(v).transpose() - target).norm(), r.maxHandle + 1e-12);
  }
  EXPECT_LT(r.rmsHandle, 0.1 * 0.3) << "soft handles in a smooth subspace follow the drag closely";
  EXPECT_LT(r.maxAnchor, 1e-3 * scene.diagonal);
  for (int v : anchors) EXPECT_LT((X.row(v) - scene.V.row(v)).norm(), 1e-3 * scene.diagonal);
  EXPECT_GT((X - scene.V).rowwise().norm().maxCoeff(), 0.25) << "the handle region did move";
}

TEST(SpectralDeformer, OnlyAConstraintChangeRefactors) {
  const Scene scene(testing::icosphere(3), 30);
  SpectralDeformer deformer(scene.basis, scene.ops, scene.V);
  const int initial = deformer.factorizationCount();
  ASSERT_TRUE(deformer.setConstraints({{{scene.within({0, 0, 1}, 0.3)}}, scene.within({0, 0, -1}, 0.3)}));
  EXPECT_EQ(deformer.factorizationCount(), initial + 1);
  for (int frame = 0; frame < 10; ++frame) {
    const HandleTransform T[] = {translation(0, 0, 0.01 * frame)};
    deformer.solve(T);
  }
  EXPECT_EQ(deformer.factorizationCount(), initial + 1) << "drag frames must reuse the factor";
  ASSERT_TRUE(deformer.setConstraints({{{scene.within({0, 1, 0}, 0.3)}}, {}}));
  EXPECT_EQ(deformer.factorizationCount(), initial + 2);
}

TEST(SpectralDeformer, InvalidConstraintsAreRejectedAndTheOldSetKept) {
  const Scene scene(testing::icosphere(2), 20);
  SpectralDeformer deformer(scene.basis, scene.ops, scene.V);
  ASSERT_TRUE(deformer.setConstraints({{{{0, 1, 2}}}, {5}}));
  EXPECT_FALSE(deformer.setConstraints({{{{0, static_cast<int>(scene.V.rows())}}}, {}}));
  EXPECT_FALSE(deformer.setConstraints({{{{}}}, {}})) << "an empty handle group";
  EXPECT_FALSE(deformer.setConstraints({{}, {-1}}));
  EXPECT_EQ(deformer.constraints().handles.size(), 1u);
}

TEST(SpectralDeformer, AComponentWithoutConstraintsStaysAtRest) {
  const Scene scene(testing::twoSpheres(2), 30);  // sphere A around x = 0, sphere B around x = 3
  SpectralDeformer deformer(scene.basis, scene.ops, scene.V);
  ASSERT_TRUE(deformer.setConstraints({{{scene.within({0, 0, 1}, 0.4)}}, scene.within({0, 0, -1}, 0.4)}));
  const HandleTransform T[] = {translation(0, 0, 0.3)};
  const Eigen::MatrixXd X = reconstruct(scene.V, scene.basis.vectors, deformer.solve(T));
  double movedA = 0.0, movedB = 0.0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double d = (X.row(i) - scene.V.row(i)).norm();
    (scene.V(i, 0) < 1.5 ? movedA : movedB) = std::max(d, scene.V(i, 0) < 1.5 ? movedA : movedB);
  }
  EXPECT_GT(movedA, 0.2);
  EXPECT_LT(movedB, 1e-6) << "sphere B has no handle and no anchor";
  EXPECT_TRUE(X.allFinite());
}

/// Mean relative change of edge lengths between rest and deformed positions.
double meanEdgeLengthChange(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& X, const Eigen::MatrixXi& F) {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, c), b = F(f, (c + 1) % 3);
      const double before = (rest.row(a) - rest.row(b)).norm();
      sum += std::abs((X.row(a) - X.row(b)).norm() - before) / before;
    }
  return sum / (3.0 * static_cast<double>(F.rows()));
}

/// Mean relative edge-length change after bending a bar (4 long, 0.2 thick) by 90° (anchored at x < 0.4, handle
/// x > 3.6) over 30 drag frames, the handle either turning with the bend or only translated (a plain drag).
/// The bar is thin on purpose: bending a bar of radius r around a radius ρ stretches and compresses its sides by
/// ±r/ρ, which no method avoids (a 0.25-radius bar keeps ≈ 4.5% in any mode), so a thick bar measures elasticity,
/// not the shearing of the linear mode.
double bentBarEdgeChange(DeformationMode mode, bool rotateHandle) {
  static const Scene bar(testing::tube(12, 64, 4.0, 0.1), 100);
  const std::vector<int> anchors = bar.where([](const Eigen::Vector3d& x) { return x.x() < 0.4; });
  const std::vector<int> handle = bar.where([](const Eigen::Vector3d& x) { return x.x() > 3.6; });
  DeformerOptions options;
  options.mode = mode;
  SpectralDeformer deformer(bar.basis, bar.ops, bar.V, options);
  EXPECT_TRUE(deformer.setConstraints({{{handle}}, anchors}));
  const double radius = 3.2 / (std::numbers::pi / 2.0);  // the free part [0.4, 3.6] becomes a quarter circle
  const int frames = 30;
  for (int frame = 1; frame <= frames; ++frame) {
    const double s = static_cast<double>(frame) / frames;
    const double angle = s * std::numbers::pi / 2.0;
    const double r = radius / s;
    const Eigen::Vector3d arcEnd(0.4 + r * std::sin(angle), r * (1.0 - std::cos(angle)), 0.0);
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    HandleTransform T;
    if (rotateHandle) T.rotation = turn;
    T.translation = arcEnd + turn * Eigen::Vector3d(0.2, 0, 0) - Eigen::Vector3d(3.8, 0, 0);
    const HandleTransform transforms[] = {T};
    deformer.solve(transforms);
  }
  return meanEdgeLengthChange(bar.V, reconstruct(bar.V, bar.basis.vectors, deformer.coefficients()), bar.F);
}

TEST(SpectralDeformer, RigidModeBendsABarWithAThirdOfTheLinearStretch) {
  // Measured: plain drag 8.7% (linear) vs 2.4% (rigid), 3.6×; turning handle 9.3% vs 3.8%, 2.4×.
  const double linearDrag = bentBarEdgeChange(DeformationMode::Linear, false);
  const double rigidDrag = bentBarEdgeChange(DeformationMode::Rigid, false);
  RecordProperty("drag_linear_vs_rigid", std::to_string(linearDrag) + " vs " + std::to_string(rigidDrag));
  EXPECT_LE(3.0 * rigidDrag, linearDrag) << "plain drag: linear " << linearDrag << ", rigid " << rigidDrag;

  const double linearTurn = bentBarEdgeChange(DeformationMode::Linear, true);
  const double rigidTurn = bentBarEdgeChange(DeformationMode::Rigid, true);
  RecordProperty("turning_linear_vs_rigid", std::to_string(linearTurn) + " vs " + std::to_string(rigidTurn));
  EXPECT_LE(2.0 * rigidTurn, linearTurn) << "turning handle: linear " << linearTurn << ", rigid " << rigidTurn;
}

// Issue 14, item 10: a pose out of range (finite but huge, non-finite, or a "rotation" that is not one) is refused:
// solve() keeps and returns the previous Z, which stays finite, and a normal pose afterwards is solved as before.
TEST(SpectralDeformer, HugeOrNonFinitePosesAreRejectedAndThePreviousZKept) {
  const Scene scene(testing::torus(40, 16), 40);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<HandleTransform> bad = {translation(1e300, 0, 0), translation(0, -1e300, 1e300),
                                      translation(0, std::nan(""), 0), translation(inf, 0, 0),
                                      translation(0, 0, 2e3 * scene.diagonal)};
  HandleTransform scaled;
  scaled.rotation *= 1e300;
  bad.push_back(scaled);
  HandleTransform sheared;
  sheared.rotation(0, 1) = 0.5;
  bad.push_back(sheared);
  HandleTransform notANumber;
  notANumber.rotation(2, 2) = std::nan("");
  bad.push_back(notANumber);
  for (DeformationMode mode : {DeformationMode::Linear, DeformationMode::Rigid}) {
    DeformerOptions options;
    options.mode = mode;
    SpectralDeformer deformer(scene.basis, scene.ops, scene.V, options);
    ASSERT_TRUE(deformer.setConstraints({{{scene.within({1.3, 0, 0}, 0.3)}}, scene.within({-1.3, 0, 0}, 0.3)}));
    const HandleTransform good[] = {translation(0, 0.2, 0)};
    const Eigen::MatrixXd before = deformer.solve(good);
    ASSERT_TRUE(before.allFinite());
    ASSERT_GT(before.cwiseAbs().maxCoeff(), 1e-6);
    for (std::size_t i = 0; i < bad.size(); ++i) {
      const HandleTransform pose[] = {bad[i]};
      const Eigen::MatrixXd after = deformer.solve(pose);
      EXPECT_TRUE(after.allFinite()) << "pose " << i << ", mode " << static_cast<int>(mode);
      EXPECT_EQ(after, before) << "pose " << i << ", mode " << static_cast<int>(mode);
      EXPECT_EQ(deformer.coefficients(), before) << "pose " << i;
      EXPECT_FALSE(poseInRange(bad[i], deformer.maxTranslation())) << "pose " << i;
    }
    EXPECT_EQ(deformer.rejectedSolves(), static_cast<int>(bad.size()));
    const HandleTransform further[] = {translation(0, 0.3, 0)};  // a normal drag recovers
    const Eigen::MatrixXd recovered = deformer.solve(further);
    EXPECT_TRUE(recovered.allFinite());
    EXPECT_GT((recovered - before).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_TRUE(poseInRange(further[0], deformer.maxTranslation()));
  }
}

}  // namespace
}  // namespace sc::spectral
