#pragma once
// A lower display resolution of a mesh: decimated rest mesh (X̂', F'), barycentric map P onto the full-resolution
// surface and the reduced basis K = P·H, so that a client reconstructs X' = X̂' + K·Z (shared/design/spectral.md §6).
//
// Wire/file layout of encodeResolutionLevel() (version 2, little-endian, no padding; n' = low-res vertices,
// f' = low-res faces, n = full-res vertices, m = basis size, z = non-zeros of P):
//
//   offset   size      field
//   0        8         magic "SCLVL\0\r\n"
//   8        4         u32 format version (kResolutionLevelVersion)
//   12       4         u32 n'
//   16       4         u32 f'
//   20       4         u32 n
//   24       4         u32 m
//   28       4         u32 z
//   32       24·n'     f64 X̂', row-major (x y z per vertex)
//   …        12·f'     i32 F', row-major, each in [0, n')
//   …        4·(n'+1)  u32 CSR row offsets of P: 0 = r_0 ≤ r_1 ≤ … ≤ r_n' = z
//   …        4·z       u32 column of each non-zero, each in [0, n)
//   …        8·z       f64 value of each non-zero
//   …        4·m       f32 scale of each column of K (finite, ≥ 0)
//   …        2·n'·m    i16 K quantised, row-major: K(i, j) ≈ scale(j)·Q(i, j) (quantized_basis.h)
//   end − 8  8         u64 checksum64 of every byte before it

#include "spectral/quantized_basis.h"
#include "spectral/vertex_ids.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace sc::spectral {

inline constexpr std::uint32_t kResolutionLevelVersion = 2;  ///< 2: K as int16 with a scale per column

/// n' by n barycentric map, row-major: row i holds the (≤ 3) weights of low-res vertex i on the full mesh.
using BarycentricMap = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// n' by m float matrix stored row-major: the reconstruction kernel streams K once per frame, row by row, and
/// a row-major K makes that one sequential read (see reconstruction_kernel.h). Levels hold K quantised
/// (QuantizedBasis, the same row-major layout in int16); float K is the reference the tests compare with.
using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// One display resolution.
struct ResolutionLevel {
  Eigen::MatrixXd restV;  ///< n' by 3 low-res rest positions X̂'.
  Eigen::MatrixXi F;      ///< f' by 3 low-res faces, indices into restV.
  BarycentricMap P;       ///< n' by n: each row ≥ 0, sums to 1, non-zeros on the corners of one full-res face.
  QuantizedBasis K;       ///< n' by m, K = P·H quantised to int16 with a float scale per column.
};

/// Barycentric map of points onto a triangle mesh: row i of P holds the barycentric weights of the closest point
/// of lowV.row(i) on (V, F) (exact closest triangle, see ClosestPointQuery). Zero weights are kept out of P.
/// @param[in] V, F  full-resolution mesh, #V = n.
/// @param[in] lowV  n' by 3 points (the low-res rest positions).
/// @param[out] distances  if not null, n' distances ‖lowV.row(i) − (P·V).row(i)‖.
/// @param[in] threads  threads for the closest-point queries.
/// @return n' by n map; P·V is the closest-point projection of lowV onto the full surface.
/// Cost: O(#F log #F) tree build plus O(n' log #F) queries.
BarycentricMap barycentricMap(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& lowV,
                              Eigen::VectorXd* distances = nullptr, int threads = 1);

/// Builds a level: P = barycentricMap(V, F, lowV), K = quantizeBasis(P·H).
/// @param[in] V, F  full-resolution rest mesh (n vertices).
/// @param[in] H  n by m basis (the harmonic basis of (V, F)).
/// @param[in] lowV, lowF  low-res rest mesh, e.g. from sc::model::decimateMesh().
/// Cost: barycentricMap() plus O(n'·m) for K.
ResolutionLevel resolutionLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H,
                                const Eigen::MatrixXd& lowV, const Eigen::MatrixXi& lowF, int threads = 1);

/// The full resolution as a level: restV = V, F, P = identity (n by n), K = quantizeBasis(H). What a host sends a
/// client that displays the full mesh, so that every client reconstructs through the same X' = X̂' + K·Z path. Cost:
/// O(n·m).
ResolutionLevel fullResolutionLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H);

/// The full-resolution vertex each displayed (low-res) vertex stands for: for displayed[k], the column with the
/// largest weight in its row of P (the first such column on ties). The one map between the two id spaces.
/// @param[in] P  n' by n barycentric map of a level.
/// @param[in] displayed  displayed vertex ids; ids outside [0, n') and rows without non-zeros are skipped.
/// @return full-resolution ids in [0, n), sorted ascending, without duplicates.
/// Cost: O(k log k) for k = displayed.size() (P has ≤ 3 non-zeros per row).
FullVertexIds dominantFullVertices(const BarycentricMap& P, std::span<const DisplayVertexId> displayed);

/// The full-resolution vertex one displayed vertex stands for (see dominantFullVertices()); nullopt for an id
/// outside [0, n') or a row without non-zeros. Cost: O(1) (≤ 3 non-zeros).
std::optional<FullVertexId> dominantFullVertex(const BarycentricMap& P, DisplayVertexId displayed);

/// Serialises a level in the layout above. Requires every count < 2³² (asserted).
/// Cost: O(24n' + 12f' + 12z + 4m + 2n'm) bytes written and checksummed.
std::vector<std::byte> encodeResolutionLevel(const ResolutionLevel& level);

/// Why decodeResolutionLevel() rejected a buffer.
enum class LevelDecodeStatus {
  Ok,
  Truncated,           ///< shorter than its header or than the sizes it declares.
  BadMagic,            ///< not a ShapeCast level.
  UnsupportedVersion,  ///< another format version.
  BadSize,             ///< longer than the declared sizes.
  BadChecksum,         ///< the trailing checksum does not match.
  BadContent,  ///< checksum fine but an index or CSR offset out of range, a non-finite number or a negative scale.
};

/// Result of decodeResolutionLevel(): a level only when status == Ok.
struct LevelDecodeResult {
  LevelDecodeStatus status = LevelDecodeStatus::Truncated;
  std::string message;  ///< human-readable reason when status != Ok.
  std::optional<ResolutionLevel> level;
  bool ok() const { return status == LevelDecodeStatus::Ok; }
};

/// Parses a buffer written by encodeResolutionLevel(). Never throws on malformed input and never reads outside
/// `bytes`: every length is checked (overflow-free) before anything is allocated or read, then the checksum,
/// then every index. Bit-exact inverse of encodeResolutionLevel().
/// Cost: O(bytes.size()).
LevelDecodeResult decodeResolutionLevel(std::span<const std::byte> bytes);

const char* toString(LevelDecodeStatus status);

}  // namespace sc::spectral
