#pragma once
// factorUpLooking(): the numeric LDLᵀ factorisation of a sparse symmetric matrix into CHOLMOD's simplicial factor,
// its rows split over threads along the elimination tree. Internal to src/spectral (InertiaLdlt::factorizeOnThreads).

#include "spectral/laplace_operators.h"

#include <cholmod.h>

namespace sc::spectral::detail {

/// Fills `factor`, CHOLMOD's simplicial analysis of A (cholmod_analyze: its permutation P and column counts), with
/// the numeric factorisation L D Lᵀ = P A Pᵀ that cholmod_factorize would compute (no pivoting; A read from its lower
/// triangle, as Eigen's CholmodSimplicialLDLT<…, Lower> passes it): a simplicial, packed, monotonic LDLᵀ factor with
/// D first in each column and its rows ascending, factor.minor = #V. A zero or non-finite pivot stops the rows of its
/// thread: factor.minor < #V (as CHOLMOD reports a failed factorisation), and the factor is not to be used.
///
/// Davis's up-looking algorithm (LDL, ACM TOMS 2005): row k of L is the sparse triangular solve with column k of
/// P A Pᵀ's upper triangle, over row k's pattern, the path from each entry up the elimination tree. A row's pattern
/// lies in its own subtree, so disjoint subtrees are independent: the tree is cut by subtreeOwners() (weights: the
/// squares of the column counts, the flops), each thread factors its subtrees' rows, then the calling thread the top's
/// rows. Entries reach a column in increasing row order either way (a subtree's rows, then the top's), so the result
/// is the same bits on any number of threads. Why not cholmod_factorize: CHOLMOD's simplicial factorisation runs on
/// one thread. At 437k vertices (shapecast-bench-factor, medians of 7, fresh factors): CHOLMOD 1.57–1.62 s, this
/// 1.49–1.59 s on one thread and 0.95–1.00 s on two; D equal to 3e-10 relative (rounding: CHOLMOD sums each row's
/// updates in another order).
///
/// Returns false when `factor` is not such an analysis of A (supernodal, not int-indexed, another size, an LLᵀ
/// factor, no column counts), A is not compressed, or CHOLMOD cannot allocate the numeric factor; `factor` is then
/// still an analysis cholmod_factorize accepts, which the caller uses instead.
/// Memory: the factor (12 bytes per entry), the permuted upper triangle (12 bytes per entry of A's), 4 ints and a
/// double per row, an int per row and thread. Cost: the factorisation's flops, Σ_j count_j², over `threads` threads.
bool factorUpLooking(const SparseMatrix& a, cholmod_factor& factor, int threads, cholmod_common& common);

}  // namespace sc::spectral::detail
