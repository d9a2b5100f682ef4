#pragma once
// Version 1 of the session file, written by ShapeCast before issue 15: the host user's constraint set with the
// handle's pose, and an undo history of (before, after) constraint+pose states of the host's drags. decodeSessionFile()
// still reads it (through decodeLegacyPayload()) and converts it to the current SessionFile: the mesh, m, mode, Z
// and the current handle and anchors are kept; the pose is dropped (Z holds the shape); the history cannot become
// edit steps (a step is a ΔZ, and re-solving a state needs the basis), so it is only counted (droppedLegacyDrags).
// The version-1 encoder stays for the tests and the fuzz seeds that exercise this path; the app writes version 2.
//
// Version 1's payload: u32 #V, u32 #F, #V·3 f64 positions, #F·3 u32 indices, u32 m, u8 mode (0 linear, 1 rigid),
//   u8 has-current, [deformation], u32 Z rows, u32 Z cols, rows·cols f64 (row-major), u32 history count,
//   u32 history index, count × (deformation before, deformation after).
//   deformation: id list handle, id list anchors, 3 f64 translation, 9 f64 rotation (row-major);
//   id list: u8 0 = "the same as the previous list of this kind" or 1 = u32 count, count × u32 ids.
// Its hostile-input guards are kept: lists bounded by #V and, expanded, by kMaxSessionFileIds (counted before any
// copy); every state's ids in range, handle non-empty, pose finite and a rotation; the history index in range.

#include "model/session_file_content.h"

#include <QByteArray>
#include <QByteArrayView>
#include <QString>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace sc::model::v1 {

inline constexpr std::uint32_t kVersion = 1;

/// One state of the host user's deformer: the constraint set (full-resolution vertex ids) and the handle's pose
/// about its rest centroid.
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

/// A version-1 file's content.
struct LegacySessionFile {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  int m = 0;
  spectral::DeformationMode mode = spectral::DeformationMode::Linear;
  std::optional<SavedDeformation> current;
  Eigen::MatrixXd Z;  ///< m by 3
  std::vector<SavedDrag> history;
  int historyIndex = 0;  ///< drags applied, 0..history.size()
};

/// The whole version-1 file (header, payload, SHA-256) as ShapeCast before issue 15 wrote it, for the tests and
/// fuzz seeds. Cost: O(size).
[[nodiscard]] QByteArray encodeLegacySessionFile(const LegacySessionFile& file);

/// Parses a version-1 payload (the bytes between the header and the checksum), checks it with version 1's rules
/// and converts it (see the header comment) into `*out`. Empty on success, else the problem. Never crashes on any
/// input. Cost: O(size + kMaxSessionFileIds) time and memory at most.
[[nodiscard]] QString decodeLegacyPayload(QByteArrayView payload, SessionFile* out);

}  // namespace sc::model::v1
