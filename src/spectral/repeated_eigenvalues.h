#pragma once
// The copies of a repeated eigenvalue that a block Lanczos run can miss, found and checked. Internal to src/spectral
// (large_mesh_eigenpairs.cpp; the spectrum slices check every index by their own counts).

#include "spectral/basis_types.h"
#include "spectral/shift_invert_operator.h"

namespace sc::spectral::detail {

/// Neighbouring eigenvalues closer than this, relative to |λ| + |σ|, count as one cluster.
inline constexpr double kClusterGap = 1e-4;

/// The size of the largest cluster of `values` (ascending): a run of neighbours each within kClusterGap·(|λ| + scale)
/// of the next. 0 for no values. Cost: O(values).
int largestCluster(const Eigen::VectorXd& values, double scale);

/// Block Lanczos from a generic start block of b columns finds b copies of an eigenvalue of any multiplicity, and the
/// further copies only as round-off brings them in: six equal spheres (the first harmonic eighteen times) gave 12 of
/// its 18 copies, then the next eigenvalues in their place, converged and M-orthonormal. A smaller multiplicity is
/// found whole. So for each cluster of at least kLanczosBlock values in `result` (the first `pairs` eigenpairs of
/// S h = λ M h from a run around σ < 0 on op, ascending), lowest first, Sylvester's count (op factored there) must
/// equal the pairs found below a point: in the gap just above the cluster, or, for the cluster that reaches index
/// pairs − 1, just below it (its copies then fill the last indices, whatever its multiplicity). While the count is
/// larger, a block Lanczos run on op at σ, deflated against every vector found (block_lanczos.h), asks for the
/// missing number, at most kLanczosBlock; its pairs join the result and the cluster is counted again (at most kRounds
/// runs). The result then keeps its first `pairs`, ascending; operatorApplications counts every solve. Without such a
/// cluster nothing is done. When a count cannot be met, result becomes NotConverged with the counts in its message; a
/// failed factorisation or run (cancelled included) is passed on. op is left factored at another shift. Cost per
/// cluster: one factorisation (symbolic analysis reused); per deflated run two more and a few dozen solves, each block
/// also reading the found vectors four times.
void completeRepeatedEigenvalues(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                                 const BasisOptions& options, BasisResult& result);

}  // namespace sc::spectral::detail
