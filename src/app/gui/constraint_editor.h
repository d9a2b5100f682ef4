#pragma once
// ConstraintEditor: one user's constraint set and drags of the handle, the same for a host and a client (each
// SessionController owns one). The handle and anchors are full-resolution vertex ids, the ids that are sent: the
// user paints displayed ids, which map to full ids (EditTarget::fullVertices: identity on a host, the level's P on
// a client), and a new displayed level shows the same full ids again (EditTarget::displayedVertices: on a coarser
// level the nearest displayed vertices stand in), so a resolution switch keeps both groups. The constraints go out
// as soon as the lock is held (at once, or when it is granted), and only when they changed. Edits accumulate
// (issue 15): the host applies a new constraint set, and each drag after a stroke end, from the shape as it is, so
// every drag's pose starts at identity about the handle's current centroid, and each drag ends with a stroke end
// (it becomes this user's step of the shared history). No Qt and no sockets: the EditTarget (the controller) says
// whether the lock is held and carries what is sent.
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
  /// Sends the handle's pose about its centroid at the drag's start; false when refused.
  virtual bool sendPose(const spectral::HandleTransform& pose) = 0;
  /// The drag ended: the host records it as this user's edit step and the next drag starts from this shape.
  virtual bool endStroke() = 0;

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
  /// The pose since beginDrag() (x ↦ R(x − c₀) + c₀ + t about the handle's centroid at the drag's start), sent as
  /// it is (the host moves the handle from where it is). False outside a drag or refused.
  bool dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation);
  /// Ends a drag: its stroke end is sent (it becomes this user's edit step).
  void endDrag();
  [[nodiscard]] bool dragging() const { return m_dragging; }

  /// The lock changed: gaining it sends the constraints (again); losing it ends a drag.
  void lockChanged(bool held);
  /// Another level is displayed: the groups keep their full ids and are shown on it (EditTarget::
  /// displayedVertices()); nothing is sent, and the next drag goes on from the shape as it is.
  void levelChanged();

  /// The constraints last sent (full ids); nullopt before any were sent.
  [[nodiscard]] std::optional<HostConstraints> sent() const;
  /// The target applied `state` itself (a restored session): it becomes the sent state; `handle` and `anchors` are
  /// its displayed ids.
  void adopt(const HostConstraints& state, spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors);

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
};

}  // namespace sc::app
