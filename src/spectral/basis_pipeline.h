#pragma once
// The whole "mesh → basis" step: operators, cache look-up, eigensolve, cache write, with timings.

#include "spectral/basis_cache.h"
#include "spectral/harmonic_basis.h"

#include <filesystem>
#include <optional>

namespace sc::spectral {

/// Result of basisForMesh().
struct BasisComputation {
  LaplaceOperators operators;  ///< S and M of the mesh (always computed: transforms need M).
  BasisResult result;          ///< status and, when ok(), the basis.
  bool cached = false;         ///< the basis came from the cache file.
  CacheReadStatus cacheStatus = CacheReadStatus::Missing;  ///< what the cache look-up found (Missing if none).
  std::filesystem::path cacheFile;                         ///< the file looked up / written (empty if no cache).
  double operatorSeconds{};                                ///< assembling S and M.
  double eigensolveSeconds{};                              ///< factorisation + Lanczos (0 on a cache hit).
  double totalSeconds{};                                   ///< everything, cache I/O included.
};

/// Computes (or loads from `cacheDir`) the manifold harmonic basis of a cleaned mesh.
///
/// With a cache folder, a file named by basisCacheFileName() is read first; a Hit skips the eigensolve, any
/// other status recomputes and (re)writes the file. Failure to write the cache is not an error.
/// @param[in] V, F  cleaned mesh: every vertex referenced, no zero-area faces (see model::cleanMesh).
/// @param[in] options  basis options (m, shift, progress/cancellation).
/// @param[in] cacheDir  folder for cache files, or std::nullopt to always solve.
/// Cost: O(#F) for the operators, then either O(#V·m) to read the cache or manifoldHarmonicBasis()'s cost.
BasisComputation basisForMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const BasisOptions& options,
                              const std::optional<std::filesystem::path>& cacheDir);

}  // namespace sc::spectral
