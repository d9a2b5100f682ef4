#pragma once
// The block size of the block Lanczos runs (block_lanczos.h, krylov_basis.h, repeated_eigenvalues.h).

namespace sc::spectral::detail {

/// Right-hand sides per block: the solves sweep the factor once for up to four (SubtreeLdltSolve; CHOLMOD's simplicial
/// solve unrolls as many), which measured 3.3 ms per right-hand side against 6.4 ms for one at a time on the 100k
/// dragon; blocks of eight converged in more columns (docs/benchmarks.md, eleventh pass).
inline constexpr int kLanczosBlock = 4;

}  // namespace sc::spectral::detail
