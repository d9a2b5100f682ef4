#pragma once
// The SciPy peer's input (bench/scipy_basis_peer.py): the generalized eigenproblem S h = λ M h of one cleaned mesh,
// written to a folder as plain text so that SciPy reads it with its own readers.

#include "spectral/laplace_operators.h"

#include <QJsonArray>
#include <QString>

namespace sc::bench {

/// Writes into the existing folder `folder`:
///  - stiffness.mtx: S as Matrix Market "coordinate real symmetric" (lower triangle, 1-based, 17 significant
///    digits, so the doubles round-trip exactly);
///  - mass.txt: the #V lumped masses, one per line (17 significant digits);
///  - problem.json: {"m", "sigma", "vertices", "reference_eigenvalues"} (σ and the eigenvalues as the project's
///    solver reported them, so that the peer solves at the same shift and compares with them).
/// @param[in] ops  S (symmetric, both triangles stored) and the mass of the mesh.
/// @return false (with `error` set) when a file cannot be written.
/// Cost: O(nnz(S)) time; about 35 bytes per stored entry of the lower triangle on disk (14 MB at 100k vertices).
bool writeScipyPeerProblem(const QString& folder, const spectral::LaplaceOperators& ops, int m, double sigma,
                           const QJsonArray& referenceEigenvalues, QString& error);

}  // namespace sc::bench
