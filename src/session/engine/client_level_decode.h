#pragma once
// The client's level check and decode (docs/protocol.md, "Model transfer" and "Levels"): a completed transfer's
// payload is checked against its SHA-256, decoded as a spectral::ResolutionLevel, checked against the session's
// shape (m, n of the Welcome) and wrapped for display (interleaved rest positions), all in one pure function that
// the adapter runs on a worker thread (ClientEngine decides when: one at a time, the latest transfer wins).

#include "spectral/display_level.h"

#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <cstdint>

namespace sc::session {

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

/// Checks, decodes and wraps `job`. Never throws (allocation failures included: reported in `error`); never
/// asserts on the payload. Thread-safe. Cost: one SHA-256 over the payload plus decodeResolutionLevel() (O(n'·m))
/// plus O(n') for the interleaved rest positions.
[[nodiscard]] DecodedLevel decodeLevel(LevelJob job);

}  // namespace sc::session
