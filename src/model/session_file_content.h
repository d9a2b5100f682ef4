#pragma once
// The content of a saved session (`.shapecast`, see session_file.h for the format and its reader and writer): the
// file's constants and the plain values it holds. A header of its own so that the format's parts (session_file_codec,
// session_file_ids, session_file_v1) depend on the values and not on the reader that uses them. No behaviour here.

#include "spectral/spectral_deformer.h"

#include <Eigen/Core>
#include <QString>
#include <QtGlobal>

#include <cstdint>
#include <optional>
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

}  // namespace sc::model
