#pragma once
// The saved session (`.shapecast`): what a host needs to host the same session again later — the rest mesh, the
// number of frequencies m, the deformation mode, the host user's current constraints and pose, the current
// coefficients Z and the undo history of the host's committed drags (each drag's state before and after, and how
// many of them are applied). Pure data and its (de)serialisation with Qt Core; no session or GUI types (the app
// converts its own types, app → model → spectral).
//
// The harmonic basis is NOT stored: it is recomputed when hosting again, or read from the basis cache, which is
// keyed by the mesh's hash — the file stores the exact (cleaned) rest positions and faces, so a host that cached
// the basis finds it again. Storing H (#V × m doubles: 18 MB for the 23k dragon at m = 100) would make the file
// ~20× larger for a saving of one cache miss.
//
// Layout, all integers little-endian, doubles IEEE-754 binary64 little-endian:
//   magic "SHAPECST" (8 bytes) | u32 version (1) | u64 payload length L | payload (L bytes) | SHA-256 (32 bytes)
//   of everything before it. Payload: u32 #V, u32 #F, #V·3 f64 positions, #F·3 u32 indices, u32 m, u8 mode
//   (0 linear, 1 rigid), u8 has-current, [deformation], u32 Z rows, u32 Z cols, rows·cols f64 (row-major),
//   u32 history count, u32 history index, count × (deformation before, deformation after).
//   deformation: id list handle, id list anchors, 3 f64 translation, 9 f64 rotation (row-major);
//   id list: u8 0 = "the same as the previous list of this kind" or 1 = u32 count, count × u32 ids.
//   (Consecutive states usually share the anchors: thousands of ids are written once, not twice per drag.)
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
inline constexpr std::uint32_t kSessionFileVersion = 1;
inline constexpr const char* kSessionFileSuffix = "shapecast";
/// The largest session file read (a 100k-vertex mesh with a long history is ≈ 10 MB).
inline constexpr qint64 kMaxSessionFileBytes = qint64{256} << 20;
/// The most vertex ids all the states of one file may hold once "same as previous" lists are expanded (256 MiB of
/// ids; ≈ 1000 drags of a 100k-vertex mesh with 60k anchors).
inline constexpr qint64 kMaxSessionFileIds = qint64{1} << 26;

/// One state of the host user's deformer: the constraint set (full-resolution vertex ids; anchors exclude the
/// handle) and the handle's pose about its rest centroid.
struct SavedDeformation {
  std::vector<int> handle;
  std::vector<int> anchors;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();

  friend bool operator==(const SavedDeformation&, const SavedDeformation&) = default;
};

/// One committed drag: the state before it and after it.
struct SavedDrag {
  SavedDeformation before;
  SavedDeformation after;

  friend bool operator==(const SavedDrag&, const SavedDrag&) = default;
};

struct SessionFile {
  Eigen::MatrixXd V;  ///< #V by 3 rest positions (the host's cleaned mesh), #V ≥ 4
  Eigen::MatrixXi F;  ///< #F by 3 faces, indices into V, #F ≥ 1
  int m = 0;          ///< frequencies, 1 ≤ m < #V
  spectral::DeformationMode mode = spectral::DeformationMode::Linear;
  std::optional<SavedDeformation> current;  ///< none before the host user set constraints
  Eigen::MatrixXd Z;                        ///< m by 3 current coefficients (or empty)
  std::vector<SavedDrag> history;           ///< oldest first
  int historyIndex = 0;                     ///< drags applied (QUndoStack::index()), 0..history.size()
};

/// Exact equality of every field (matrices of different sizes are unequal). Cost: O(size).
[[nodiscard]] bool sameSessionFile(const SessionFile& a, const SessionFile& b);

/// Why a file could not be read: a readable sentence naming the problem (not a session file, newer version,
/// truncated, checksum mismatch, an index out of range, …).
struct SessionFileError {
  QString message;
};

using SessionFileResult = std::variant<SessionFile, SessionFileError>;

/// Checks what readSessionFile() would check of the content (sizes, index ranges, finite numbers, m, history
/// index). Empty when valid, else the first problem. Cost: O(#V + #F + ids in the history).
[[nodiscard]] QString validateSessionFile(const SessionFile& file);

/// The file's bytes (header, payload, checksum). `file` should be valid (validateSessionFile); an invalid one is
/// written as it is and refused by decodeSessionFile(). Cost: O(size); SHA-256 over all of it.
[[nodiscard]] QByteArray encodeSessionFile(const SessionFile& file);

/// Parses and validates bytes from encodeSessionFile(). Never throws or crashes on any input: foreign data, a newer
/// version, a truncated or corrupted file (SHA-256 mismatch), more than kMaxSessionFileBytes, counts larger than
/// the data, an id list longer than the mesh's vertex count, lists whose "same as previous" copies would hold more
/// than kMaxSessionFileIds ids (refused while counting, before copying), ids out of range or non-finite numbers give
/// a SessionFileError. Cost: O(size + kMaxSessionFileIds) time, O(size + kMaxSessionFileIds) memory at most.
[[nodiscard]] SessionFileResult decodeSessionFile(const QByteArray& bytes);

/// Writes encodeSessionFile(file) to `path` through QSaveFile (a temporary file renamed over `path` only once
/// complete, so an existing file is never left half-written). nullopt on success, else the reason.
[[nodiscard]] std::optional<QString> writeSessionFile(const QString& path, const SessionFile& file);

/// Reads and decodes `path`; an unreadable file (or one over kMaxSessionFileBytes, refused unread) is a
/// SessionFileError too.
[[nodiscard]] SessionFileResult readSessionFile(const QString& path);

/// True when `path` starts with the session file magic (a cheap test to tell a session file from a mesh).
[[nodiscard]] bool isSessionFile(const QString& path);

}  // namespace sc::model
