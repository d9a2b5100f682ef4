#pragma once
// The client's level check and decode (docs/protocol.md, "Model transfer" and "Levels"): a completed transfer's
// payload is checked against its SHA-256, decoded as a spectral::ResolutionLevel, checked against the session's
// shape (m, n of the Welcome) and wrapped for display (interleaved rest positions), all in one pure function that
// the adapter runs on a worker thread (ClientEngine decides when: one at a time, the latest transfer wins).
// Also the limits a client puts on what a host announces before any byte of a level arrives (docs/security.md,
// "Hostile host"): the session's shape, the sizes a LevelList may list, the transfer a ModelBegin may start, and
// the magnitudes of positions, K and Z that a client shows. All pure and thread-safe.

#include "session/wire/control_messages.h"
#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <cstdint>

namespace sc::session {

/// Largest |value| a client shows: rest coordinates, K entries (levels) and coefficients Z (Keyframes, datagram
/// frames). Far above any real model (metres or millimetres), far below what overflows float32 in X̂' + K·Z.
inline constexpr double kMaxAbsCoordinate = 1e9;
/// Most faces per vertex a listed level may have (real meshes: about 2).
inline constexpr std::uint32_t kMaxFacesPerVertex = 8;

/// The byte sizes an encoded level (spectral/resolution_level.h) of `vertices` n', `faces` f' and `rows` m can have:
/// 44 + 28·n' + 12·f' + 4·m + 2·n'·m + 12·z bytes with z (non-zeros of P) in [0, 3·n']. Exact in 64 bits.
struct PayloadBounds {
  std::uint64_t min = 0;
  std::uint64_t max = 0;
};
[[nodiscard]] PayloadBounds levelPayloadBounds(std::uint64_t vertices, std::uint64_t faces, std::uint64_t rows);

/// Empty when a Welcome's shape (m rows, n vertices) is one a host could serve: 1 ≤ m, 1 ≤ n, and its full model
/// (n' = n, one face at least, z = n) fits one transfer (kMaxTransferSize); otherwise the readable reason.
[[nodiscard]] QString checkSessionShape(std::uint16_t rows, std::uint32_t vertices);

/// Empty when every level of `list` fits the session (m, n): 1 ≤ n' ≤ n (n' = n for the full model, id 0),
/// f' ≤ kMaxFacesPerVertex·n', payload bytes within levelPayloadBounds(n', f', m); otherwise the readable reason.
/// Cost: O(levels).
[[nodiscard]] QString checkLevelList(const LevelList& list, std::uint16_t rows, std::uint32_t vertices);

/// Empty when `begin` announces a listed level: a level of `list` with its vertex count and exactly its payload
/// bytes (the full model for FullModel). Otherwise the readable reason: nothing may be received for it.
[[nodiscard]] QString checkAnnouncement(const ModelBegin& begin, const LevelList& list);

/// True when every entry of `values` is finite and |entry| ≤ kMaxAbsCoordinate. Cost: O(size).
[[nodiscard]] bool displayable(const Eigen::Ref<const Eigen::MatrixXd>& values);

/// One completed transfer to check and decode.
struct LevelJob {
  QByteArray payload;             ///< an encoded spectral::ResolutionLevel, as received (not yet checked)
  QByteArray sha256;              ///< the transfer's announced SHA-256 (ModelBegin)
  std::uint16_t rowCount = 0;     ///< m of the session: K must have m columns
  std::uint32_t vertexCount = 0;  ///< n of the session: P must have n columns
};

/// What decodeLevel() hands back: the level or a reason.
struct DecodedLevel {
  QByteArray payload;                  ///< the checked payload (empty on failure)
  spectral::SharedDisplayLevel level;  ///< null on failure
  QString error;                       ///< set exactly when `level` is null
};

/// Checks, decodes and wraps `job`: refuses, besides a checksum, decode or shape mismatch, an empty level (no
/// vertex or no face) and one whose coordinates or K entries are not displayable (|x| > kMaxAbsCoordinate).
/// Never throws (allocation failures included: reported in `error`); never asserts on the payload. Thread-safe. Cost:
/// one SHA-256 over the payload plus decodeResolutionLevel() (O(n'·m)) plus O(n') for the interleaved rest positions.
[[nodiscard]] DecodedLevel decodeLevel(LevelJob job);

}  // namespace sc::session
