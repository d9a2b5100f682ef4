#pragma once
// ConstraintEditor: one user's constraint set and drags of the handle, the same for a host and a client (each
// SessionController owns one). It keeps the displayed vertex ids the user painted, maps them to full-resolution
// ids when sending (EditTarget::fullIds: identity on a host, the level's P on a client), sends the constraints as
// soon as the lock is held (at once, or when it is granted), sends each drag's poses and ends each drag with a
// stroke end. Edits accumulate (issue 15): the host applies a new constraint set, and each drag after a stroke
// end, from the shape as it is, so every drag's pose starts at identity about the handle's current centroid. No Qt
// and no sockets: the EditTarget (the controller) says whether the lock is held and carries what is sent.
// Cost: O(k log k) per send for k ids; O(1) per pose.

#include "app/gui/session_settings.h"
#include "spectral/spectral_deformer.h"
#include "spectral/vertex_ids.h"

#include <Eigen/Core>

#include <optional>

namespace sc::app {

/// What a ConstraintEditor sends through: a session's local user.
class EditTarget {
 public:
  virtual ~EditTarget() = default;
  /// True when this user holds the lock (sends would be accepted).
  [[nodiscard]] virtual bool canDrag() const = 0;
  /// The full-resolution vertices that displayed ids stand for: sorted, unique, ids out of range dropped.
  [[nodiscard]] virtual spectral::FullVertexIds fullIds(const spectral::DisplayVertexIds& displayed) const = 0;
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

  /// Replaces the handle and/or the anchors (displayed ids) and sends them when the lock is held (a vertex in both
  /// is a handle). True when the constraints were sent now.
  bool setSelection(spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors);
  bool setHandle(spectral::DisplayVertexIds handle);
  bool setAnchors(spectral::DisplayVertexIds anchors);
  [[nodiscard]] const spectral::DisplayVertexIds& handle() const { return m_handle; }
  [[nodiscard]] const spectral::DisplayVertexIds& anchors() const { return m_anchors; }

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
  /// A new displayed level: the painted ids mean nothing on it (cleared, nothing sent).
  void clear();

  /// The constraints last sent (full ids); nullopt before any were sent.
  [[nodiscard]] std::optional<HostConstraints> sent() const;
  /// The target applied `state` itself (a restored session): it becomes the sent state; `handle` and `anchors` are
  /// its displayed ids.
  void adopt(const HostConstraints& state, spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors);

 private:
  bool send();

  EditTarget& m_target;
  spectral::DisplayVertexIds m_handle;
  spectral::DisplayVertexIds m_anchors;
  spectral::FullVertexIds m_sentHandle;  ///< the full ids of the constraints last sent
  spectral::FullVertexIds m_sentAnchors;
  bool m_sent = false;
  bool m_hadLock = false;
  bool m_dragging = false;
};

}  // namespace sc::app
