#pragma once
// The types of manifoldHarmonicBasis(): the basis, the solver choice and settings, and the result with its status.
// Apart from harmonic_basis.h so that the solvers behind it (lanczos_solver, hierarchical_basis) need not include
// harmonic_basis.h, which dispatches to them.

#include "spectral/laplace_operators.h"

#include <functional>
#include <string>

namespace sc::spectral {

/// The first m manifold harmonics of a mesh.
struct HarmonicBasis {
  Eigen::VectorXd eigenvalues;  ///< m eigenvalues λ_0 ≤ … ≤ λ_{m−1} (≈0 once per connected component).
  Eigen::MatrixXd vectors;      ///< #V by m matrix H, M-orthonormal: HᵀMH = I.
  double shift{};               ///< σ < 0 the shift-invert operator (S − σM)⁻¹M was factorised at.

  Eigen::Index vertexCount() const { return vectors.rows(); }
  Eigen::Index size() const { return vectors.cols(); }
};

/// Which eigensolver manifoldHarmonicBasis() uses.
enum class BasisSolver {
  /// Spectra's shift-invert Lanczos on a simplicial CHOLMOD factor: one right-hand side at a time, converged to
  /// `tolerance` on the Ritz values. The reference (tests compare against it). Single-vector Lanczos may miss copies
  /// of an exactly multiple eigenvalue (equal components): measured on two equal spheres and a torus at m = 27.
  Lanczos,
  /// Coarse start + block subspace iteration (hierarchical_basis.h): eigenvectors of the coarsest of a few
  /// smoothed-aggregation Galerkin levels (each ≥ 2(m + guard) vertices), prolonged level by level with shift-invert
  /// subspace iterations, Rayleigh–Ritz and locking on each, until every wanted pair's relative residual on the
  /// mesh is below `residualTolerance`. Meshes too small to coarsen (#V < about 10(m + guard)) use Lanczos.
  Hierarchical,
  /// Spectrum slicing (spectrum_slices.h): a few block shift-invert Lanczos runs (block_lanczos.h) around shifts
  /// spread over the band, on parallel threads, each placed in the spectrum by the inertia of its own LDLᵀ factor
  /// and checked against its neighbours where their windows overlap. Lanczos below sliceMinimumVertices, one block
  /// Lanczos run above sliceMaximumVertices; the hierarchical solver when a check fails.
  Slices,
};

/// Settings of manifoldHarmonicBasis(). Defaults follow shared/design/spectral.md §2.2.
struct BasisOptions {
  int m = 100;  ///< number of eigenpairs; must satisfy 1 ≤ m < #V.
  /// See BasisSolver. Spectrum slicing is the default: on the 2-core test machine it takes about half Lanczos's wall
  /// time from 100k vertices up (docs/benchmarks.md, "Eigensolvers side by side"); below sliceMinimumVertices it is
  /// Lanczos.
  BasisSolver solver = BasisSolver::Slices;
  /// Hierarchical: bound on detail::relativeResiduals() ‖Sh − λMh‖_{M⁻¹}/(|λ| + |σ|) of every returned pair.
  /// 1e-6 bounds the eigenvalue error by about 1e-12·(|λ|+|σ|)²/gap and the angle to the eigenspace by
  /// 1e-6·(|λ|+|σ|)/gap (gap: distance to the rest of the spectrum), see subspace_iteration.h.
  double residualTolerance = 1e-6;
  /// Hierarchical: extra columns b − m of the iterated block; 0 means max(m/2, 16). More: fewer sweeps, more
  /// dense work per sweep.
  int guardVectors = 0;
  int maxSweeps = 100;  ///< Hierarchical: sweeps per level before NotConverged (the 100k dragon needs 4 at 1e-6).
  /// Lanczos subspace size; 0 means min(#V, max(5m/2, m + 20)). More vectors: fewer restarts, more memory
  /// (#V·ncv doubles). 5m/2 measured faster than 2m on the 100k dragon (one fewer restart, same 251 solves).
  int ncv = 0;
  /// Slices: how many (0: one per hardware thread, at least 2, at most m/12). More: less orthogonalisation, more
  /// factorisations and overlap.
  int slices = 0;
  /// Slices: threads running them (0: the hardware's, at most `slices`).
  int sliceThreads = 0;
  /// Slices: each slice runs block Lanczos (block_lanczos.h), or Spectra's single-vector Lanczos when false or when
  /// the block run does not converge within 4 columns per pair.
  bool blockLanczos = true;
  /// Slices: meshes with fewer vertices use Lanczos (slicing pays for its extra factorisations on large meshes).
  Eigen::Index sliceMinimumVertices = 20000;
  /// Slices: meshes with more vertices run one block Lanczos (blockLanczosEigenpairs(): one factor, one Krylov
  /// basis, its solves and sweeps split over the cores). Each running slice holds its own factor and #V·K Krylov
  /// vectors: on the 437k scan the slices took 11.6–14.4 s and 1.82 GB against 10.7–11.7 s and 1.34 GB for the one
  /// run; on the 100k dragon the two were within the noise (one run 2.3–2.5 s, slices 2.4–2.8 s), and the slices
  /// keep their exact count of every index there; on the 23k dragon the slices won, 0.42 s against 0.48 s
  /// (docs/benchmarks.md, seventh pass).
  Eigen::Index sliceMaximumVertices = 200000;
  /// σ = −shiftFactor·4π/area. Negative so that S − σM is SPD (Cholesky applies, S itself is singular);
  /// about the first non-zero eigenvalue of a sphere of the same area, which keeps the operator well scaled.
  double shiftFactor = 1.0;
  /// Relative convergence tolerance on the Ritz values (Spectra's test; block Lanczos uses the same).
  double tolerance = 1e-10;
  /// `tolerance` of the large-mesh path above sliceMaximumVertices (large_mesh_eigenpairs.h: its block Lanczos run,
  /// the deflated runs and the fallback to Spectra's), where each solve costs most. On the 437k scan 1e-8 gave the
  /// eigenvalues of the 1e-10 run to 1.8e-14 of |λ| + |σ| with 292 solves instead of 308, and a max residual
  /// ‖Sh − λMh‖ of 7.7e-7 instead of 8.5e-9: the level the 100k dragon (3e-7) and the 1M mesh (4.3e-7) reach at
  /// 1e-10, where round-off sets it (docs/benchmarks.md, eighth pass).
  double largeMeshTolerance = 1e-8;
  int maxRestarts = 1000;  ///< Spectra's iteration limit.
  /// Called with the estimated fraction done in [0, 1] from inside the solve; return false to cancel.
  std::function<bool(double fraction)> progress;
};

/// How manifoldHarmonicBasis() ended.
enum class BasisStatus {
  Ok,
  InvalidInput,         ///< m out of range, non-positive mass, or S not square / mismatched.
  FactorizationFailed,  ///< Cholesky of S − σM failed (S not PSD or M singular).
  NotConverged,         ///< Spectra stopped before all m eigenpairs converged.
  Cancelled,            ///< the progress callback returned false.
};

/// Result of manifoldHarmonicBasis(): a basis only when status == Ok.
struct BasisResult {
  BasisStatus status = BasisStatus::InvalidInput;
  std::string message;  ///< human-readable reason when status != Ok; when Ok, why a solver fell back (or empty).
  HarmonicBasis basis;
  int operatorApplications{};  ///< solves with the factor (the dominant cost; right-hand sides, not blocks).
  BasisSolver solver = BasisSolver::Lanczos;  ///< the solver that produced the basis (after any fallback).
  int slices{};                               ///< Slices: the number of slices (0 for the other solvers).
  int sweeps{};          ///< Hierarchical: Rayleigh–Ritz sweeps on the fine mesh (0 for Lanczos).
  double maxResidual{};  ///< max relative residual ‖Sh − λMh‖_{M⁻¹}/(|λ| + |σ|) over the basis.
  bool ok() const { return status == BasisStatus::Ok; }
};

}  // namespace sc::spectral
