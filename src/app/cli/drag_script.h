#pragma once
// Drag scripts: a JSON description of handles, anchors and keyframes that replays a drag without a mouse
// (`shapecast-cli deform`). Format: docs/drag-script.md.
//
// Three steps, each testable on its own: parseDragScript() (JSON → DragScript, every key checked),
// resolveConstraints() (selections → vertex indices on the rest mesh) and frameTimes()/poseAt()/transformAt()
// (keyframes → one HandleTransform per frame). Qt Core and Eigen only: no mesh I/O, no solver.

#include "spectral/spectral_deformer.h"

#include <Eigen/Core>
#include <QByteArray>
#include <QString>

#include <optional>
#include <variant>
#include <vector>

namespace sc::app {

/// All vertices within `radiusPct` % of the rest bounding-box diagonal of vertex `vertex` (Euclidean, rest mesh).
struct SphereSelection {
  int vertex = 0;
  double radiusPct = 0.0;
};

/// One handle group: an explicit vertex list or a sphere (exactly one of the two is set).
struct HandleSelection {
  std::vector<int> vertices;
  std::optional<SphereSelection> sphere;
};

/// All vertices farther than `distancePct` % of the rest diagonal from vertex `fromVertex` (Euclidean, rest mesh).
struct FartherThanSelection {
  int fromVertex = 0;
  double distancePct = 0.0;
};

/// The anchors: an explicit vertex list, a farther-than selection, or neither (no anchors).
struct AnchorSelection {
  std::vector<int> vertices;
  std::optional<FartherThanSelection> fartherThan;
};

/// The pose of every handle group at one time: translation in % of the rest diagonal, XYZ Euler angles in degrees
/// (applied about X, then Y, then Z, about each group's rest centroid: R = Rz·Ry·Rx).
struct DragPose {
  Eigen::Vector3d translatePct = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotateDeg = Eigen::Vector3d::Zero();
};

/// One keyframe: the pose at time t (seconds).
struct DragKeyframe {
  double t = 0.0;
  DragPose pose;
};

/// A parsed, validated script. Keyframe times are strictly increasing; fps > 0.
struct DragScript {
  std::vector<HandleSelection> handles;  ///< at least one.
  AnchorSelection anchors;
  std::vector<DragKeyframe> frames;  ///< at least one.
  double fps = 30.0;                 ///< frames per second at which the keyframes are sampled.
};

/// Parses and validates a drag script. Unknown keys are errors (a typo must not silently mean "zero"), so are
/// wrong types, negative or non-integer vertex indices, empty lists, non-positive radii or fps, and keyframe
/// times that do not increase. Vertex ranges are checked later, by resolveConstraints().
/// @return the script, or an error message that names the offending key (e.g. "frames[1].translate_pct: …").
std::variant<DragScript, QString> parseDragScript(const QByteArray& json);

/// Reads the file at `path` and parses it (the message names the file when it cannot be read).
std::variant<DragScript, QString> readDragScript(const QString& path);

/// Resolves the selections against the rest mesh into vertex indices, each group and the anchors sorted.
/// Sphere and farther-than selections measure Euclidean distance on the rest positions, relative to
/// spectral::boundingBoxDiagonal(rest). Handles win over anchors: an anchor that is also a handle vertex is dropped.
/// Errors (message naming the key): a vertex index ≥ #V, two handle groups sharing a vertex, a farther-than
/// selection that selects nothing.
/// @param[in] rest  #V by 3 rest positions.
/// Cost: O(#V) per sphere / farther-than selection, plus sorting.
std::variant<spectral::ConstraintSet, QString> resolveConstraints(const DragScript& script,
                                                                  const Eigen::MatrixXd& rest);

/// The sampling times: frames[0].t, then every 1/fps up to the last keyframe time, which is always included
/// (one frame for a single keyframe).
std::vector<double> frameTimes(const DragScript& script);

/// The pose at time t: linear interpolation of translation and Euler angles between the surrounding keyframes,
/// clamped to the first / last keyframe outside their range.
DragPose poseAt(const DragScript& script, double t);

/// The transform of a pose on a mesh whose rest diagonal is `diagonal`: translation = translatePct / 100 ·
/// diagonal, rotation = Rz·Ry·Rx from rotateDeg.
spectral::HandleTransform transformAt(const DragPose& pose, double diagonal);

}  // namespace sc::app
