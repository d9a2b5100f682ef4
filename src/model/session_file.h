#pragma once
// The saved session (`.shapecast`): what a host needs to host the same session again later — the rest mesh, the
// number of frequencies m, the deformation mode, the host user's current constraint set (handle and anchors), the
// current coefficients Z (the shape) and the session's edit history: every committed drag (a stroke, by anyone) as
// the change ΔZ it made to the coefficients, with its author and whether it is undone (undo subtracts ΔZ, redo adds
// it back). Pure data and its (de)serialisation with Qt Core; no session or GUI types (the app converts its own
// types, app → model → spectral).
//
// The harmonic basis is NOT stored: it is recomputed when hosting again, or read from the basis cache, which is
// keyed by the mesh's hash — the file stores the exact (cleaned) rest positions and faces, so a host that cached
// the basis finds it again. Storing H (#V × m doubles: 18 MB for the 23k dragon at m = 100) would make the file
// ~20× larger for a saving of one cache miss. A step's ΔZ is m × 3 doubles (2.4 kB at m = 100).
//
// Layout (version 2), all integers little-endian, doubles IEEE-754 binary64 little-endian:
//   magic "SHAPECST" (8 bytes) | u32 version (2) | u64 payload length L | payload (L bytes) | SHA-256 (32 bytes)
//   of everything before it. Payload: u32 #V, u32 #F, #V·3 f64 positions, #F·3 u32 indices, u32 m, u8 mode
//   (0 linear, 1 rigid), u8 has-current, [id list handle, id list anchors], u32 Z rows, u32 Z cols, rows·cols f64
//   (row-major), u32 step count, count × (u8 author length, author UTF-8 bytes, u8 undone (0 or 1), m·3 f64 ΔZ
//   (row-major: exactly m rows and 3 columns)).
//   id list: u32 count, count × u32 full-resolution vertex ids (ascending).
// Version 1 (ShapeCast before issue 15: a pose and an undo history of constraint+pose states) is still read, see
// session_file_v1.h; writing always writes version 2.
// The SHA-256 is computed with OpenSSL (EVP_sha256), as the session's other digests.

#include "model/session_file_content.h"

#include <Eigen/Core>
#include <QByteArray>
#include <QString>

#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

namespace sc::model {

/// Exact equality of every field (matrices of different sizes are unequal). Cost: O(size).
[[nodiscard]] bool sameSessionFile(const SessionFile& a, const SessionFile& b);

/// Why a file could not be read: a readable sentence naming the problem (not a session file, newer version,
/// truncated, checksum mismatch, an index out of range, …).
struct SessionFileError {
  QString message;
};

using SessionFileResult = std::variant<SessionFile, SessionFileError>;

/// Checks what readSessionFile() would check of the content: the mesh (sizes, finite positions, face indices), m,
/// Z (m × 3 or empty, finite), the current constraints (SavedConstraints' rules, ids in range), at most
/// kMaxSavedEditSteps steps, each with an author of at most kMaxStepAuthorBytes UTF-8 bytes (a string UTF-8 can
/// carry: no lone surrogate) and a finite m × 3 ΔZ, droppedLegacyDrags ≥ 0. Empty when valid, else the first
/// problem. Cost: O(#V + #F + ids + steps·m).
[[nodiscard]] QString validateSessionFile(const SessionFile& file);

/// The file's bytes in version 2 (header, payload, checksum). `file` should be valid (validateSessionFile); an
/// invalid one is written so that decodeSessionFile() refuses it (as it is, but a ΔZ that is not m × 3 as m × 3
/// NaNs, an author over 255 bytes cut there, one UTF-8 cannot carry as an invalid byte). droppedLegacyDrags is not
/// written. Cost: O(size); SHA-256 over all of it.
[[nodiscard]] QByteArray encodeSessionFile(const SessionFile& file);

/// Parses and validates bytes from encodeSessionFile() (version 2) or from ShapeCast's earlier version 1 (see
/// session_file_v1.h: converted, its undo history counted in droppedLegacyDrags). Never throws or crashes on any
/// input: foreign data, a newer version, a truncated or corrupted file (SHA-256 mismatch), more than
/// kMaxSessionFileBytes, counts larger than the data (checked before allocating), an id list longer than the
/// mesh's vertex count, more than kMaxSavedEditSteps steps, an author over kMaxStepAuthorBytes or not valid UTF-8,
/// ids out of range or non-finite numbers give a SessionFileError. Cost: O(size) time and memory (version 1: plus
/// kMaxSessionFileIds at most, its "same as previous" lists).
[[nodiscard]] SessionFileResult decodeSessionFile(const QByteArray& bytes);

/// Writes encodeSessionFile(file) to `path` through QSaveFile (a temporary file renamed over `path` only once
/// complete, so an existing file is never left half-written); an invalid `file` is refused unwritten. nullopt on
/// success, else the reason.
[[nodiscard]] std::optional<QString> writeSessionFile(const QString& path, const SessionFile& file);

/// Reads and decodes `path`; an unreadable file (or one over kMaxSessionFileBytes, refused unread) is a
/// SessionFileError too.
[[nodiscard]] SessionFileResult readSessionFile(const QString& path);

/// True when `path` starts with the session file magic (a cheap test to tell a session file from a mesh).
[[nodiscard]] bool isSessionFile(const QString& path);

}  // namespace sc::model
