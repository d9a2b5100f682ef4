#include "spectral/spectral_deformer.h"

#include "spectral/rigid_subspace.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace sc::spectral {
namespace {

/// Relative size of the ridge added to the m×m system so that null-space directions of unconstrained components
/// are pinned at zero (they stay at rest) instead of making the system singular.
constexpr double kRegularisation = 1e-9;

bool validConstraints(const ConstraintSet& constraints, Eigen::Index vertexCount) {
  auto valid = [vertexCount](int v) { return v >= 0 && v < vertexCount; };
  for (const HandleGroup& group : constraints.handles)
    if (group.vertices.empty() || !std::all_of(group.vertices.begin(), group.vertices.end(), valid)) return false;
  return std::all_of(constraints.anchors.begin(), constraints.anchors.end(), valid);
}

}  // namespace

bool poseInRange(const HandleTransform& pose, double maxTranslation) {
  if (!pose.translation.allFinite() || !pose.rotation.allFinite()) return false;
  if (!(pose.translation.norm() <= maxTranslation)) return false;
  const double orthogonality =
      (pose.rotation.transpose() * pose.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  return orthogonality <= kPoseRotationTolerance &&
         std::abs(pose.rotation.determinant() - 1.0) <= kPoseRotationTolerance;
}

double maxPoseTranslation(const Eigen::MatrixXd& rest) {
  const double diagonal = rest.rows() > 0 ? (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm() : 0.0;
  return kMaxPoseTranslationDiagonals * std::max(diagonal, 1e-12);
}

SpectralDeformer::SpectralDeformer(const HarmonicBasis& basis, const LaplaceOperators& operators,
                                   const Eigen::MatrixXd& rest, const DeformerOptions& options)
    : m_basis(basis),
      m_operators(operators),
      m_rest(rest),
      m_options(options),
      m_Z(Eigen::MatrixXd::Zero(basis.size(), 3)) {
  m_maxTranslation = maxPoseTranslation(rest);
  setConstraints({});
}

SpectralDeformer::~SpectralDeformer() = default;

bool SpectralDeformer::setConstraints(const ConstraintSet& constraints) {
  std::optional<PreparedConstraints> prepared = prepare(constraints);
  if (!prepared) return false;
  install(std::move(*prepared));
  return true;
}

bool SpectralDeformer::setConstraints(const ConstraintSet& constraints, const Eigen::MatrixXd& base) {
  if (!validBase(base)) return false;
  std::optional<PreparedConstraints> prepared = prepare(constraints);
  if (!prepared) return false;
  install(std::move(*prepared), base);
  return true;
}

std::optional<PreparedConstraints> SpectralDeformer::prepare(const ConstraintSet& constraints) const {
  if (!validConstraints(constraints, m_rest.rows())) return std::nullopt;
  const Eigen::VectorXd& lambda = m_basis.eigenvalues;
  const double lambdaMax = std::max(std::abs(lambda(m_basis.size() - 1)), 1e-300);
  const bool rigid = m_options.mode == DeformationMode::Rigid;
  PreparedConstraints out;

  // === step 1: energy diagonal (Λ² linear, Λ rigid) and constraint weight w²
  const Eigen::VectorXd energy = rigid ? Eigen::VectorXd(lambda.cwiseMax(0.0)) : Eigen::VectorXd(lambda.cwiseAbs2());
  out.weight = m_options.constraintWeight * (rigid ? lambdaMax : lambdaMax * lambdaMax);

  // === step 2: A = E + w² H_Cᵀ H_C over every constrained row, plus a tiny ridge
  std::vector<int> rows;
  for (const HandleGroup& group : constraints.handles)
    rows.insert(rows.end(), group.vertices.begin(), group.vertices.end());
  rows.insert(rows.end(), constraints.anchors.begin(), constraints.anchors.end());
  Eigen::MatrixXd A = energy.asDiagonal();
  if (!rows.empty()) {  // BLAS's syrk rejects an empty update
    const Eigen::MatrixXd Hc = m_basis.vectors(rows, Eigen::all);
    A.selfadjointView<Eigen::Lower>().rankUpdate(Hc.transpose(), out.weight);
  }
  A.diagonal().array() += kRegularisation * (out.weight + energy.maxCoeff());
  out.factor.compute(A.selfadjointView<Eigen::Lower>());

  // === step 3: per-group moments so that a frame's right-hand side costs O(m) per group
  for (const HandleGroup& group : constraints.handles) {
    const Eigen::MatrixXd Hg = m_basis.vectors(group.vertices, Eigen::all);
    const Eigen::MatrixX3d Xg = m_rest(group.vertices, Eigen::all);
    const Eigen::Vector3d centroid = Xg.colwise().mean().transpose();
    out.groupCentroids.push_back(centroid);
    out.groupMoments.push_back(out.weight * Hg.transpose() * (Xg.rowwise() - centroid.transpose()));
    out.groupSums.push_back(out.weight * Hg.colwise().sum().transpose());
  }
  out.constraints = constraints;
  return out;
}

void SpectralDeformer::install(PreparedConstraints prepared) {
  m_weight = prepared.weight;
  m_factor = std::move(prepared.factor);
  m_groupMoments = std::move(prepared.groupMoments);
  m_groupSums = std::move(prepared.groupSums);
  m_groupCentroids = std::move(prepared.groupCentroids);
  m_constraints = std::move(prepared.constraints);
  ++m_factorizations;
  if (m_options.mode == DeformationMode::Rigid && !m_rigid)
    m_rigid = std::make_unique<RigidSubspace>(m_basis, m_operators, m_rest, m_options.rigidClusters);
  m_Z.setZero(m_basis.size(), 3);
  m_base.setZero(m_basis.size(), 3);
  m_energyBase.setZero(m_basis.size(), 3);
}

void SpectralDeformer::install(PreparedConstraints prepared, const Eigen::MatrixXd& base) {
  install(std::move(prepared));
  rebase(base);
}

bool SpectralDeformer::validBase(const Eigen::MatrixXd& base) const {
  return base.rows() == m_basis.size() && base.cols() == 3 && base.allFinite();
}

bool SpectralDeformer::rebase(const Eigen::MatrixXd& base) {
  if (!validBase(base)) return false;
  // Moments and centroids about the base shape X₀ = X̂ + H Z₀: w² Σ_i H_iᵀ (x₀_i − c₀)ᵀ per group.
  for (std::size_t g = 0; g < m_constraints.handles.size(); ++g) {
    const std::vector<int>& ids = m_constraints.handles[g].vertices;
    const Eigen::MatrixXd Hg = m_basis.vectors(ids, Eigen::all);
    const Eigen::MatrixX3d Xg = m_rest(ids, Eigen::all) + Hg * base;
    const Eigen::Vector3d centroid = Xg.colwise().mean().transpose();
    m_groupCentroids[g] = centroid;
    m_groupMoments[g] = m_weight * Hg.transpose() * (Xg.rowwise() - centroid.transpose());
  }
  m_base = base;
  m_energyBase = m_options.mode == DeformationMode::Rigid
                     ? Eigen::MatrixXd(m_basis.eigenvalues.cwiseMax(0.0).asDiagonal() * base)
                     : Eigen::MatrixXd::Zero(base.rows(), 3);
  m_Z = base;
  return true;
}

Eigen::MatrixXd SpectralDeformer::constraintRightHandSide(std::span<const HandleTransform> transforms) const {
  // w² H_Cᵀ (P_C − X₀_C) with, per group, P − X₀ = (R − I)(x₀ − c) + t; anchors contribute zero.
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m_basis.size(), 3);
  const std::size_t groups = std::min(transforms.size(), m_groupMoments.size());
  for (std::size_t g = 0; g < groups; ++g) {
    const HandleTransform& T = transforms[g];
    rhs.noalias() += m_groupMoments[g] * (T.rotation - Eigen::Matrix3d::Identity()).transpose();
    rhs.noalias() += m_groupSums[g] * T.translation.transpose();
  }
  return rhs;
}

Eigen::MatrixXd SpectralDeformer::change(std::span<const HandleTransform> transforms) const {
  const std::size_t used = std::min(transforms.size(), m_groupMoments.size());
  const auto inRange = [this](const HandleTransform& T) { return poseInRange(T, m_maxTranslation); };
  if (!std::all_of(transforms.begin(), transforms.begin() + static_cast<std::ptrdiff_t>(used), inRange)) {
    return Eigen::MatrixXd::Zero(m_basis.size(), 3);
  }
  return m_factor.solve(constraintRightHandSide(transforms));
}

const Eigen::MatrixXd& SpectralDeformer::solve(std::span<const HandleTransform> transforms) {
  const std::size_t used = std::min(transforms.size(), m_groupMoments.size());
  const auto inRange = [this](const HandleTransform& T) { return poseInRange(T, m_maxTranslation); };
  if (!std::all_of(transforms.begin(), transforms.begin() + static_cast<std::ptrdiff_t>(used), inRange)) {
    ++m_rejectedSolves;
    return m_Z;
  }
  const Eigen::MatrixXd rhs = constraintRightHandSide(transforms);
  // Z = Z₀ + ΔZ. Linear: A ΔZ = rhs. Rigid: the normal equations A Z = w² H_CᵀH_C Z₀ + rhs + r(Z) in ΔZ form,
  // A ΔZ = rhs + r(Z) − E Z₀ (r the rotation term, E the energy diagonal), warm-started from the last Z.
  Eigen::MatrixXd Z;
  if (m_options.mode == DeformationMode::Linear) {
    Z = m_base + m_factor.solve(rhs);
  } else {
    Z = m_Z;
    for (int iteration = 0; iteration < m_options.rigidIterations; ++iteration)
      Z = m_base + m_factor.solve(rhs + m_rigid->rotationRightHandSide(Z) - m_energyBase);
  }
  if (!Z.allFinite()) {
    ++m_rejectedSolves;
    return m_Z;
  }
  m_Z = std::move(Z);
  return m_Z;
}

Eigen::MatrixX3d SpectralDeformer::targets(std::span<const HandleTransform> transforms) const {
  std::size_t count = 0;
  for (const HandleGroup& group : m_constraints.handles) count += group.vertices.size();
  Eigen::MatrixX3d P(static_cast<Eigen::Index>(count), 3);
  Eigen::Index row = 0;
  for (std::size_t g = 0; g < m_constraints.handles.size(); ++g) {
    const HandleTransform T = g < transforms.size() ? transforms[g] : HandleTransform{};
    for (int v : m_constraints.handles[g].vertices) {
      const Eigen::Vector3d x = (m_rest.row(v) + m_basis.vectors.row(v) * m_base).transpose();
      P.row(row++) = (T.rotation * (x - m_groupCentroids[g]) + m_groupCentroids[g] + T.translation).transpose();
    }
  }
  return P;
}

ConstraintResidual SpectralDeformer::residual(std::span<const HandleTransform> transforms) const {
  ConstraintResidual r;
  const Eigen::MatrixX3d P = targets(transforms);
  Eigen::Index row = 0;
  double sumSquares = 0.0;
  for (const HandleGroup& group : m_constraints.handles)
    for (int v : group.vertices) {
      const Eigen::RowVector3d x = m_rest.row(v) + m_basis.vectors.row(v) * m_Z;
      const double miss = (x - P.row(row++)).norm();
      r.maxHandle = std::max(r.maxHandle, miss);
      sumSquares += miss * miss;
    }
  if (row > 0) r.rmsHandle = std::sqrt(sumSquares / static_cast<double>(row));
  const Eigen::MatrixXd change = m_Z - m_base;
  for (int v : m_constraints.anchors) r.maxAnchor = std::max(r.maxAnchor, (m_basis.vectors.row(v) * change).norm());
  return r;
}

}  // namespace sc::spectral
