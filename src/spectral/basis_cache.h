#pragma once
// On-disk cache of manifold harmonic bases, so a second run on the same mesh skips the eigensolve.
//
// File layout (version 1, little-endian, no padding):
//
//   offset        size   field
//   0             8      magic "SCMHB\0\r\n" (the CR LF catches text-mode mangling)
//   8             4      u32 format version (kBasisCacheVersion)
//   12            4      u32 n, vertex count
//   16            4      u32 m, basis size
//   20            4      u32 solver that computed it: 0 Lanczos or spectrum slicing, 1 hierarchical (BasisSolver; this
//   field was
//                          "reserved, 0" before issue 19, so older files read as Lanczos)
//   24            8      u64 content hash of the cleaned mesh (meshContentHash)
//   32            8      f64 σ, the shift the basis was computed at
//   40            8·m    f64 eigenvalues λ_0..λ_{m−1}
//   40+8m         8·n·m  f64 H, column-major
//   40+8m+8nm     8      u64 checksum of every byte before it (checksum64)
//
// A file that is short, long, has another magic or version, an unknown solver, or fails its checksum is Corrupt; a
// valid file for another mesh, size, shift or solver is Mismatch. Writes go to a unique temporary file beside the cache
// (mkstemp, created exclusively: concurrent writers never share one, a planted link is never followed), flushed to disk
// and renamed into place, so a crash mid-write never leaves a truncated cache behind.

#include "spectral/harmonic_basis.h"

#include <cstdint>
#include <filesystem>
#include <span>

namespace sc::spectral {

inline constexpr std::uint32_t kBasisCacheVersion = 1;

/// What identifies a cached basis.
struct BasisCacheKey {
  std::uint64_t meshHash{};  ///< meshContentHash(V, F) of the cleaned mesh.
  std::uint32_t n{};         ///< vertex count.
  std::uint32_t m{};         ///< basis size.
  double shift{};            ///< σ (depends on the mesh area and BasisOptions::shiftFactor).
  /// The solver asked for (BasisOptions::solver). Lanczos and Slices share entries (both converge every pair with
  /// Spectra to BasisOptions::tolerance); the hierarchical solver's (converged to residualTolerance) are kept apart.
  BasisSolver solver = BasisSolver::Lanczos;
  bool operator==(const BasisCacheKey&) const = default;
};

enum class CacheReadStatus {
  Hit,       ///< the basis was read.
  Missing,   ///< no such file.
  Corrupt,   ///< unreadable, truncated, wrong magic/version/size or bad checksum.
  Mismatch,  ///< a valid file for another key.
};

/// 64-bit content hash of a mesh's exact coordinates and indices (and their counts). Cost: O(#V + #F).
std::uint64_t meshContentHash(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// 64-bit checksum of a byte buffer (FNV-1a over 64-bit words, then the tail bytes). Cost: O(size).
std::uint64_t checksum64(std::span<const std::byte> bytes);

/// File name for a key: "<hash as 16 hex digits>-n<n>-m<m>.mhb" for Lanczos (the name before the solver was
/// recorded, so those caches stay valid), "<…>-m<m>-hierarchical.mhb" for the hierarchical solver.
std::filesystem::path basisCacheFileName(const BasisCacheKey& key);

/// Reads a cached basis; `basis` is written only on Hit. Never throws. Cost: O(n·m) read and checksum.
CacheReadStatus readBasisCache(const std::filesystem::path& file, const BasisCacheKey& expected, HarmonicBasis& basis);

/// Writes a basis atomically (unique temporary "<file>.XXXXXX", mode 0600, fsync, rename), creating parent folders.
/// Returns false on any I/O error, leaving no temporary behind.
/// Cost: O(n·m).
bool writeBasisCache(const std::filesystem::path& file, const BasisCacheKey& key, const HarmonicBasis& basis);

const char* toString(CacheReadStatus status);

}  // namespace sc::spectral
