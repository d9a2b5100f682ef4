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

#include "spectral/spectral_deformer.h"

#include <Eigen/Core>
#include <QByteArray>
#include <QString>

#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

namespace sc::model {

inline constexpr char kSessionFileMagic[8] = {'S', 'H', 'A', 'P', 'E', 'C', 'S', 'T'};
/// The version written; versions 1 and 2 are read.
inline constexpr std::uint32_t kSessionFileVersion = 2;
inline constexpr const char* kSessionFileSuffix = "shapecast";
/// The largest session file read (a 100k-vertex mesh with 256 steps at m = 100 is ≈ 3 MB).
inline constexpr qint64 kMaxSessionFileBytes = qint64{256} << 20;
/// The most vertex ids all the states of one version-1 file may hold once its "same as previous" lists are
/// expanded (256 MiB of ids; ≈ 1000 drags of a 100k-vertex mesh with 60k anchors).
inline constexpr qint64 kMaxSessionFileIds = qint64{1} << 26;
/// The most edit steps a file holds (the app keeps at most this many; older ones are dropped when saving).
inline constexpr int kMaxSavedEditSteps = 256;
/// The longest author name, in UTF-8 bytes.
inline constexpr int kMaxStepAuthorBytes = 64;

/// The host user's constraint set: full-resolution vertex ids, each list ascending without repeats, the handle
/// non-empty, no id in both. No pose: the shape is in SessionFile::Z.
struct SavedConstraints {
  std::vector<int> handle;
  std::vector<int> anchors;

  friend bool operator==(const SavedConstraints&, const SavedConstraints&) = default;
};

/// One edit step of the session's shared history: a committed drag, as the change it made to the coefficients.
struct SavedEditStep {
  QString author;         ///< the user who made it, at most kMaxStepAuthorBytes UTF-8 bytes (may be empty)
  Eigen::MatrixXd delta;  ///< ΔZ, m by 3, finite
  bool undone = false;    ///< undone (ΔZ not in Z) or applied

  /// Exact equality (matrices of different sizes are unequal).
  friend bool operator==(const SavedEditStep& a, const SavedEditStep& b) {
    return a.author == b.author && a.undone == b.undone && a.delta.rows() == b.delta.rows() &&
           a.delta.cols() == b.delta.cols() && a.delta == b.delta;
  }
};

struct SessionFile {
  Eigen::MatrixXd V;  ///< #V by 3 rest positions (the host's cleaned mesh), #V ≥ 4
  Eigen::MatrixXi F;  ///< #F by 3 faces, indices into V, #F ≥ 1
  int m = 0;          ///< frequencies, 1 ≤ m < #V
  spectral::DeformationMode mode = spectral::DeformationMode::Linear;
  std::optional<SavedConstraints> current;  ///< the host user's constraints; none before they set any
  Eigen::MatrixXd Z;                        ///< m by 3 current coefficients, or empty (0 × 0: the rest shape)
  std::vector<SavedEditStep> steps;         ///< the edit history, oldest first, at most kMaxSavedEditSteps
  /// Read from a version-1 file: the drags of its undo history, which cannot be restored (0 otherwise). Never
  /// written; the app tells the user the older file's undo history was not restored.
  int droppedLegacyDrags = 0;
};

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
