#pragma once
// ConstraintEditor: one user's constraint set and drags of the handle, the same for a host and a client (each
// SessionController owns one). The handle and anchors are full-resolution vertex ids, the ids that are sent: the
// user paints displayed ids, which map to full ids (EditTarget::fullVertices: identity on a host, the level's P on
// a client), and a new displayed level shows the same full ids again (EditTarget::displayedVertices: on a coarser
// level the nearest displayed vertices stand in), so a resolution switch keeps both groups and the pose. The
// constraints go out as soon as the lock is held (at once, or when it is granted), and only when they changed; the
// viewport's per-drag poses are composed with the pose the previous drags of the same constraints left. No Qt and
// no sockets: the EditTarget (the controller) says whether the lock is held and carries what is sent.
// Cost: O(k log k) per edit or send for k ids; O(1) per pose; a level switch as EditTarget::displayedVertices().

#include "app/gui/session_settings.h"
#include "spectral/level_vertex_map.h"
#include "spectral/spectral_deformer.h"
#include "spectral/vertex_ids.h"

#include <Eigen/Core>

#include <optional>
#include <utility>

namespace sc::app {

/// What a ConstraintEditor sends through: a session's local user.
class EditTarget {
 public:
  virtual ~EditTarget() = default;
  /// True when this user holds the lock (sends would be accepted).
  [[nodiscard]] virtual bool canDrag() const = 0;
  /// The full-resolution vertices that displayed ids stand for, with where each lies at rest: ids sorted, unique,
  /// ids out of range dropped (spectral::locateFullVertices()).
  [[nodiscard]] virtual spectral::LocatedFullVertices fullVertices(
      const spectral::DisplayVertexIds& displayed) const = 0;
  /// The displayed vertices that show full-resolution ones on the displayed level, sorted and unique
  /// (spectral::displayedVertices()).
  [[nodiscard]] virtual spectral::DisplayVertexIds displayedVertices(
      const spectral::LocatedFullVertices& full) const = 0;
  /// Sends one handle group and the anchors (disjoint, sorted); false when refused (nothing sent).
  virtual bool sendConstraints(const spectral::FullVertexIds& handle, const spectral::FullVertexIds& anchors) = 0;
  /// Sends the handle's pose about its rest centroid; false when refused.
  virtual bool sendPose(const spectral::HandleTransform& pose) = 0;

 protected:
  EditTarget() = default;
  EditTarget(const EditTarget&) = default;
  EditTarget& operator=(const EditTarget&) = default;
};

class ConstraintEditor final {
 public:
  explicit ConstraintEditor(EditTarget& target) : m_target(target) {}

  /// Replaces the handle and the anchors (displayed ids: mapped to full ids now) and sends them when the lock is
  /// held and they differ from the constraints last sent (a vertex in both is a handle). setHandle() and
  /// setAnchors() replace one group and keep the other's full ids. True when the constraints were sent now.
  bool setSelection(spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors);
  bool setHandle(spectral::DisplayVertexIds handle);
  bool setAnchors(spectral::DisplayVertexIds anchors);
  /// The groups as displayed ids on the displayed level.
  [[nodiscard]] const spectral::DisplayVertexIds& handle() const { return m_handle.displayed; }
  [[nodiscard]] const spectral::DisplayVertexIds& anchors() const { return m_anchors.displayed; }
  /// The groups as full-resolution ids (what is sent; the anchors before the handle-wins rule).
  [[nodiscard]] const spectral::FullVertexIds& fullHandle() const { return m_handle.full.ids; }
  [[nodiscard]] const spectral::FullVertexIds& fullAnchors() const { return m_anchors.full.ids; }

  /// Starts a drag: false without the lock or a handle, or when the constraints cannot be sent.
  bool beginDrag();
  /// The pose since beginDrag() (x ↦ R(x − c₀) + c₀ + t about the handle's centroid at the drag's start), composed
  /// with the pose (R₀, t₀) the previous drags left into (R·R₀, t₀ + t) and sent. False outside a drag or refused.
  bool dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation);
  void endDrag() { m_dragging = false; }
  [[nodiscard]] bool dragging() const { return m_dragging; }

  /// The lock changed: gaining it sends the constraints (again); losing it ends a drag.
  void lockChanged(bool held);
  /// Another level is displayed: the groups keep their full ids and are shown on it (EditTarget::
  /// displayedVertices()); nothing is sent, and the next drag goes on from the pose the previous drags left.
  void levelChanged();

  /// The constraints last sent (full ids) with the pose of the last drag; nullopt before any were sent.
  [[nodiscard]] std::optional<HostDeformation> sent() const;
  /// The target applied `state` itself (undo/redo): it becomes the sent state and the next drag starts from its
  /// pose; `handle` and `anchors` are its displayed ids.
  void adopt(const HostDeformation& state, spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors);

 private:
  /// One group: the ids as painted or shown, and the full ids they stand for.
  struct Group {
    spectral::DisplayVertexIds displayed;
    spectral::LocatedFullVertices full;
  };
  [[nodiscard]] Group painted(spectral::DisplayVertexIds displayed) const;
  /// Handle and anchors as sent: the anchors without the handle's vertices.
  [[nodiscard]] std::pair<spectral::FullVertexIds, spectral::FullVertexIds> constraints() const;
  /// A group changed: sends when the constraints differ from those last sent.
  bool edited();
  bool send();

  EditTarget& m_target;
  Group m_handle;
  Group m_anchors;
  spectral::FullVertexIds m_sentHandle;  ///< the full ids of the constraints last sent
  spectral::FullVertexIds m_sentAnchors;
  bool m_sent = false;
  bool m_hadLock = false;
  bool m_dragging = false;
  spectral::HandleTransform m_base;  ///< pose left by the previous drags (R₀, t₀)
  spectral::HandleTransform m_last;  ///< the last pose sent
};

}  // namespace sc::app
