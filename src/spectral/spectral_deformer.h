#pragma once
// Spectral mesh deformation in displacement form: X = X̂ + HZ, handles solved in the m-dimensional subspace.
// See shared/design/spectral.md §3 (linear) and §5 (rigid, subspace ARAP).
//
// Edits build on each other (issue 15): a constraint set acts from a BASE shape X₀ = X̂ + H Z₀ (rest by default;
// rebase() moves it to the current shape). Anchors hold where they are in X₀, a handle group's pose moves it from
// where it is in X₀ about its centroid there, and a solve returns Z = Z₀ + ΔZ with ΔZ the smoothest change that
// meets the targets: in linear mode, min tr(ΔZᵀΛ²ΔZ) + w² ‖H_C ΔZ − (P_C − X₀_C)‖², so identity poses give
// exactly Z₀ (nothing moves when someone new takes over). In rigid mode the ARAP energy is still measured against
// the rest shape (its rotations fit rest edges), with the targets above: the constrained vertices hold, the free
// parts relax as-rigid-as-possible around them.

#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace sc::spectral {

class RigidSubspace;

/// A set of vertices moved together by one rigid transform (rotation about the group's rest centroid, then
/// translation).
struct HandleGroup {
  std::vector<int> vertices;
};

/// What the user constrains: handle groups (moved) and anchors (held where they are in the base shape).
struct ConstraintSet {
  std::vector<HandleGroup> handles;
  std::vector<int> anchors;
};

/// The pose of one handle group: target x = R (x₀ − c) + c + t, x₀ the vertex in the base shape and c the group's
/// centroid there (the rest shape and rest centroid until SpectralDeformer::rebase()).
struct HandleTransform {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

/// How far a pose may move a handle: this many diagonals of the rest mesh's bounding box (a drag beyond it is no
/// edit but garbage, and 1e300 would overflow the coefficients and every reconstruction).
inline constexpr double kMaxPoseTranslationDiagonals = 1e3;
/// How far a pose's rotation may be from orthonormal (max |RᵀR − I|, |det R − 1|); wire quantisation is ~1e-7.
inline constexpr double kPoseRotationTolerance = 1e-3;

/// Whether `pose` is one the deformer accepts: every number finite, |t| ≤ `maxTranslation`, R a rotation within
/// kPoseRotationTolerance. Pure; O(1).
[[nodiscard]] bool poseInRange(const HandleTransform& pose, double maxTranslation);

/// kMaxPoseTranslationDiagonals times the bounding-box diagonal of `rest` (#V by 3): the `maxTranslation` of the
/// deformer of that mesh. Cost: O(#V).
[[nodiscard]] double maxPoseTranslation(const Eigen::MatrixXd& rest);

enum class DeformationMode {
  Linear,  ///< truncated biharmonic energy tr(ZᵀΛ²Z): one prefactored m×m solve per frame.
  Rigid,   ///< subspace as-rigid-as-possible (clustered local rotations + the same kind of global solve).
};

struct DeformerOptions {
  DeformationMode mode = DeformationMode::Linear;
  /// Soft-constraint weight relative to the energy's scale: w² = constraintWeight · λ_{m−1}² (linear) or
  /// constraintWeight · λ_{m−1} (rigid). Measured on a 90° bend of a 1040-vertex bar (m = 100) with 224 constrained
  /// vertices: 0.1 leaves a handle miss of 0.07% of the bar length for a pure drag and keeps the shape smooth;
  /// 10³ (shared/design/spectral.md §4) fits the over-determined constraints (c > m) at any cost and the bar
  /// explodes (mean edge-length change 800%). Larger values only help when handles have far fewer vertices than m.
  double constraintWeight = 0.1;
  int rigidIterations = 10;  ///< local–global iterations per frame (warm-started from the previous frame).
  int rigidClusters = 200;   ///< rotation clusters (k-means on the low harmonics); capped at #V / 4.
};

/// Residual of a solve at the constrained vertices, in model units.
struct ConstraintResidual {
  double maxHandle = 0.0;  ///< max ‖x_i − target_i‖ over handle vertices.
  double rmsHandle = 0.0;  ///< root mean square of the same.
  double maxAnchor = 0.0;  ///< max ‖x_i − x₀_i‖ over anchors (x₀: the base shape).
};

/// A constraint set with its factored m×m system and per-group moments: made by SpectralDeformer::prepare() (const,
/// so it may run on another thread while the deformer solves) and put in place by install() (moves only).
struct PreparedConstraints {
  ConstraintSet constraints;
  double weight = 0.0;
  std::vector<Eigen::MatrixX3d> groupMoments;  ///< about the rest shape; rebase() recomputes them
  std::vector<Eigen::VectorXd> groupSums;
  std::vector<Eigen::Vector3d> groupCentroids;
  Eigen::LLT<Eigen::MatrixXd> factor;
};

/// Pre-factored spectral deformer of one mesh (the host's per-frame engine).
///
/// Usage: construct once per basis, call setConstraints() when the handle/anchor set changes (forms and factors the
/// m×m system: O(c·m² + m³)), then solve() per drag frame (O(m·groups + m²), independent of #V and of the number of
/// handle vertices). A mesh component without any constraint stays at rest (its null-space directions are pinned
/// by a tiny regularisation instead of making the system singular).
class SpectralDeformer {
 public:
  /// @param basis  H (#V by m) and Λ; kept by reference: must outlive the deformer.
  /// @param operators  S and M of the same mesh (S's edge weights are used by the rigid mode); kept by reference.
  /// @param rest  #V by 3 rest positions X̂; kept by reference.
  SpectralDeformer(const HarmonicBasis& basis, const LaplaceOperators& operators, const Eigen::MatrixXd& rest,
                   const DeformerOptions& options = {});
  ~SpectralDeformer();
  SpectralDeformer(const SpectralDeformer&) = delete;
  SpectralDeformer& operator=(const SpectralDeformer&) = delete;

  /// Replaces the constraint set and refactors. Returns false (and keeps the previous set) if a vertex index is out
  /// of range or a handle group is empty.
  bool setConstraints(const ConstraintSet& constraints);
  /// The expensive half of setConstraints() (O(c·m² + m³)): reads only the basis, the rest positions and the
  /// options, which never change, so it may run on another thread while this deformer solves. nullopt when invalid.
  std::optional<PreparedConstraints> prepare(const ConstraintSet& constraints) const;
  /// The cheap half: puts a prepared set in place (moves; builds the rigid clusters on first use) with the rest
  /// shape as its base: Z = 0.
  void install(PreparedConstraints prepared);
  /// install(), then rebase(base): the new constraint set acts from the shape `base` (m by 3, finite) describes.
  void install(PreparedConstraints prepared, const Eigen::MatrixXd& base);
  /// setConstraints() from the shape `base` (m by 3, finite): what a session does when someone sets new
  /// constraints, so that the shape carries on from where it is. False (nothing changed) as setConstraints().
  bool setConstraints(const ConstraintSet& constraints, const Eigen::MatrixXd& base);

  /// Makes `base` (m by 3 coefficients, finite; else false and nothing changes) the shape the current constraints
  /// act from, and the current Z: anchors hold where they are in it, and identity poses leave it unchanged. Called
  /// when a stroke ends (the next one starts from here) or an edit is undone under the current constraints.
  /// Cost: O(handle vertices · m).
  bool rebase(const Eigen::MatrixXd& base);
  /// The base shape's coefficients Z₀ (zero until rebase()).
  [[nodiscard]] const Eigen::MatrixXd& base() const { return m_base; }

  /// Solves one frame: one transform per handle group (fewer: missing groups stay at rest; extra ones ignored).
  /// A used transform out of range (poseInRange() with maxTranslation()) or a solve that is not finite is rejected:
  /// Z stays the previous one (counted in rejectedSolves()), so Z is always finite.
  /// @return Z, m by 3 displacement coefficients (what is streamed). Zero transforms give Z = 0.
  const Eigen::MatrixXd& solve(std::span<const HandleTransform> transforms);

  /// The linear part of what `transforms` do from the base: A⁻¹·rhs(transforms), m by 3, with A the factored
  /// system (missing groups at identity, which adds nothing). In linear mode solve(T) = base() + change(T) and the
  /// change of several groups' poses is the sum of each one's alone: how a session splits a frame moved by several
  /// people into each one's share. In rigid mode it is the first-order share (the rotation term is left out).
  /// Poses out of range give zero. Cost: O(m·groups + m²); const, no state.
  [[nodiscard]] Eigen::MatrixXd change(std::span<const HandleTransform> transforms) const;

  /// The largest handle translation solve() accepts: kMaxPoseTranslationDiagonals rest bounding-box diagonals.
  double maxTranslation() const { return m_maxTranslation; }
  /// How many solve() calls were rejected (a pose out of range or a non-finite result).
  int rejectedSolves() const { return m_rejectedSolves; }

  /// The last Z returned by solve() (zero before any solve).
  const Eigen::MatrixXd& coefficients() const { return m_Z; }

  /// Residual of coefficients() at the constrained vertices for the given transforms (targets from the base
  /// shape). Cost: O(c·m).
  ConstraintResidual residual(std::span<const HandleTransform> transforms) const;

  /// How many times the m×m system was factored (changes only in setConstraints()).
  int factorizationCount() const { return m_factorizations; }

  const ConstraintSet& constraints() const { return m_constraints; }
  DeformationMode mode() const { return m_options.mode; }

 private:
  /// w² H_Cᵀ (P_C − X̂_C) for the given transforms, from the per-group moments: O(m) per group.
  Eigen::MatrixXd constraintRightHandSide(std::span<const HandleTransform> transforms) const;
  [[nodiscard]] bool validBase(const Eigen::MatrixXd& base) const;
  /// Target positions of every handle vertex, in group order.
  Eigen::MatrixX3d targets(std::span<const HandleTransform> transforms) const;

  const HarmonicBasis& m_basis;
  const LaplaceOperators& m_operators;
  const Eigen::MatrixXd& m_rest;
  DeformerOptions m_options;
  ConstraintSet m_constraints;
  double m_weight = 0.0;                          ///< w² actually used.
  std::vector<Eigen::MatrixX3d> m_groupMoments;   ///< per group: w² Σ_i H_iᵀ (x₀_i − c)ᵀ, m by 3 (base shape)
  std::vector<Eigen::VectorXd> m_groupSums;       ///< per group: w² Σ_i H_iᵀ, m.
  std::vector<Eigen::Vector3d> m_groupCentroids;  ///< per group: its centroid c in the base shape
  Eigen::MatrixXd m_base;                         ///< Z₀, m by 3: the shape the constraints act from
  Eigen::MatrixXd m_energyBase;                   ///< E Z₀ (rigid mode's energy diagonal times the base)
  Eigen::LLT<Eigen::MatrixXd> m_factor;
  Eigen::MatrixXd m_Z;
  std::unique_ptr<RigidSubspace> m_rigid;  ///< clusters and rotation terms, built on first use of the rigid mode
  int m_factorizations = 0;
  double m_maxTranslation = 0.0;
  int m_rejectedSolves = 0;
};

}  // namespace sc::spectral
