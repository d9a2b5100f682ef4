#pragma once
// The copies of a repeated eigenvalue that a block Lanczos run can miss, found and checked. Internal to src/spectral
// (large_mesh_eigenpairs.cpp; the spectrum slices check every index by their own counts).

#include "spectral/basis_types.h"
#include "spectral/shift_invert_operator.h"

namespace sc::spectral::detail {

/// Neighbouring eigenvalues closer than this, relative to |λ| + |σ|, count as one cluster.
inline constexpr double kClusterGap = 1e-4;

/// The last index of the cluster that starts at `first` in `values` (ascending): the values within
/// kClusterGap·(|λ| + scale) of values[first] (so a cluster never spans more than one such gap). Cost: O(cluster).
Eigen::Index clusterEnd(const Eigen::VectorXd& values, Eigen::Index first, double scale);

/// A block Lanczos run from a generic start block of b columns finds b copies of an eigenvalue of any multiplicity,
/// and the further copies only as round-off brings them in: six equal spheres (the first harmonic eighteen times)
/// gave 12 of its 18 copies, then the next eigenvalues in their place, converged and M-orthonormal. A smaller
/// multiplicity is found whole; a single-vector run (Spectra's, the fallback) may miss copies of any multiplicity.
/// So, in `result` (the first `pairs` eigenpairs of S h = λ M h from a run around σ < 0 on op, ascending), lowest
/// first: after a block run each cluster of at least kLanczosBlock values, after a single-vector run
/// (`singleVectorRun`) everything up to index pairs − 1 and its cluster, is counted by Sylvester's law (op factored
/// there): the pairs found below a point must be all there are — the point lies in the gap just above the range, or,
/// for a block run's cluster that reaches index pairs − 1, just below it (its copies then fill the last indices,
/// whatever its multiplicity). While the count is larger, a block Lanczos run on op at σ, deflated against every
/// vector found (block_lanczos.h), asks for the missing number, at most kLanczosBlock; its pairs join the result and
/// the range is counted again. The result then keeps its first `pairs`, ascending; operatorApplications counts every
/// solve. Without such a range nothing is done. result becomes NotConverged, with the counts in its message, when a
/// count is below what was found, when a deflated run finds none of the missing pairs, or after 16 deflated runs;
/// Cancelled when options.progress asks so before a count; a failed factorisation or run is passed on. op is left
/// factored at another shift.
/// Cost per range: one factorisation (symbolic analysis reused); per deflated run two more and a few dozen solves,
/// each block also reading the found vectors four times; #V·(found) doubles more while the pairs are merged.
void completeRepeatedEigenvalues(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                                 const BasisOptions& options, bool singleVectorRun, BasisResult& result);

}  // namespace sc::spectral::detail
