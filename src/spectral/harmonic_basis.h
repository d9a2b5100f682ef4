#pragma once
// Manifold harmonic basis (Vallet & Lévy 2008): the first m eigenpairs of S h = λ M h.

#include "spectral/basis_types.h"
#include "spectral/laplace_operators.h"

#include <optional>
#include <string_view>

namespace sc::spectral {

/// Computes the first m eigenpairs of S h = λ M h with the solver chosen in the options (BasisSolver):
/// Spectra's SymGEigsShiftSolver in shift-invert mode around σ < 0 on a CHOLMOD (simplicial) Cholesky factor of
/// S − σM, or the hierarchical block subspace iteration around the same σ.
///
/// Eigenvalues come out ascending; eigenvectors are M-orthonormal and have deterministic signs (each column's
/// entry of largest magnitude is positive). Solver failure is reported through the status, never as a silently
/// wrong basis.
///
/// @param[in] ops  stiffness S (#V by #V, PSD) and lumped mass (#V, > 0), e.g. from laplaceOperators().
/// @param[in] options  m, Lanczos size, shift, tolerance, progress/cancellation.
/// @return status, message and, on success, the basis.
/// Cost (Lanczos): one sparse Cholesky of S − σM, then ≈ 2.5m triangular solve pairs plus O(#V·ncv²) Lanczos
/// orthogonalisation per restart; memory O(nnz(L) + #V·ncv). Hierarchical: see hierarchical_basis.h.
BasisResult manifoldHarmonicBasis(const LaplaceOperators& ops, const BasisOptions& options = {});

/// max |HᵀMH − I| over all entries: the M-orthonormality defect of a basis.
/// Cost: O(#V·m²), summed over bands of rows: memory O(m²) plus one band, not a second #V × m matrix (800 MB at 1M
/// vertices and m = 100).
double orthonormalityError(const Eigen::MatrixXd& H, const Eigen::VectorXd& mass);

/// max over columns of the relative residual ‖S h − λ M h‖_{M⁻¹}/(|λ| + |σ|) (see subspace_iteration.h).
/// Cost: O(nnz(S)·m + #V·m), in chunks of 8 columns on the hardware's threads; memory one #V × 8 buffer per thread,
/// reused for each chunk (not a whole S·H: 350 MB at 437k vertices and m = 100; nor fresh temporaries per chunk,
/// whose page faults and column-at-a-time reads of S took 1.7 s at 1M, now 0.7 s).
double maxRelativeResidual(const LaplaceOperators& ops, const HarmonicBasis& basis);

/// "lanczos", "slices" or "hierarchical".
const char* toString(BasisSolver solver);

/// The solver toString() names `name`, or nullopt.
std::optional<BasisSolver> basisSolverNamed(std::string_view name);

/// Human-readable name of a status ("ok", "cancelled", …).
const char* toString(BasisStatus status);

}  // namespace sc::spectral
