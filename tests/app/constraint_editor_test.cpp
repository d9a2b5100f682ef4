// ConstraintEditor without a session: a fake EditTarget records what would be sent. Covers when constraints go out
// (now with the lock, else when it is granted), the id map and the handle-wins rule, the composition of a drag's
// poses with the previous drags', a lost lock ending a drag, the state undo/redo reads and restores, unchanged
// constraints not sent again, and a resolution switch keeping the groups (full ids) and the pose.

#include "app/gui/constraint_editor.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace sc::app {
namespace {

using spectral::DisplayVertexId;
using spectral::DisplayVertexIds;
using spectral::FullVertexId;
using spectral::FullVertexIds;

DisplayVertexIds displayed(std::vector<std::uint32_t> ids) { return spectral::vertexIds<DisplayVertexId>(ids); }
FullVertexIds full(std::vector<std::uint32_t> ids) { return spectral::vertexIds<FullVertexId>(ids); }

/// A client's level in miniature: displayed id d stands for full id step·d (step 10 at first; a resolution switch
/// changes it), which lies at x = full id / 10; displayed ids ≥ 100 are out of range. Records the sends.
class FakeTarget final : public EditTarget {
 public:
  bool locked = false;
  bool refuse = false;
  std::uint32_t step = 10;
  std::vector<std::pair<FullVertexIds, FullVertexIds>> constraints;
  std::vector<spectral::HandleTransform> poses;

  [[nodiscard]] bool canDrag() const override { return locked; }
  [[nodiscard]] spectral::LocatedFullVertices fullVertices(const DisplayVertexIds& ids) const override {
    FullVertexIds out;
    for (const DisplayVertexId id : ids) {
      if (id.value < 100) out.emplace_back(step * id.value);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    Eigen::MatrixXd points = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(out.size()), 3);
    for (std::size_t k = 0; k < out.size(); ++k) points(static_cast<Eigen::Index>(k), 0) = out[k].value / 10.0;
    return {out, points};
  }
  /// Exact where step divides the full id, else the displayed vertex nearest to its point (x = 10·d/step).
  [[nodiscard]] DisplayVertexIds displayedVertices(const spectral::LocatedFullVertices& full) const override {
    DisplayVertexIds out;
    for (std::size_t k = 0; k < full.ids.size(); ++k) {
      const std::uint32_t f = full.ids[k].value;
      if (f % step == 0) {
        out.emplace_back(f / step);
      } else if (full.points.rows() > 0) {
        out.emplace_back(
            static_cast<std::uint32_t>(std::lround(full.points(static_cast<Eigen::Index>(k), 0) * 10.0 / step)));
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  bool sendConstraints(const FullVertexIds& handle, const FullVertexIds& anchors) override {
    if (refuse) return false;
    constraints.emplace_back(handle, anchors);
    return true;
  }
  bool sendPose(const spectral::HandleTransform& pose) override {
    if (refuse) return false;
    poses.push_back(pose);
    return true;
  }
  bool endStroke() override {
    if (!locked) return false;
    ++strokeEnds;
    return true;
  }
  int strokeEnds = 0;
};

TEST(ConstraintEditor, SendsWhenTheLockIsGrantedMappedAndTheHandleWins) {
  FakeTarget target;
  ConstraintEditor editor(target);
  EXPECT_FALSE(editor.setSelection(displayed({3, 1, 3, 500}), displayed({1, 2})));  // no lock: kept, not sent
  EXPECT_TRUE(target.constraints.empty());
  EXPECT_EQ(editor.handle(), displayed({3, 1, 3, 500}));
  EXPECT_FALSE(editor.sent().has_value());

  target.locked = true;
  editor.lockChanged(true);
  ASSERT_EQ(target.constraints.size(), 1u);
  EXPECT_EQ(target.constraints[0].first, full({10, 30}));  // mapped, sorted, unique, out of range dropped
  EXPECT_EQ(target.constraints[0].second, full({20}));     // 1 is a handle vertex: not an anchor
  ASSERT_TRUE(editor.sent().has_value());
  EXPECT_EQ(editor.sent()->handle, full({10, 30}));

  EXPECT_TRUE(editor.setAnchors(displayed({4})));  // held: sent at once, the handle kept
  ASSERT_EQ(target.constraints.size(), 2u);
  EXPECT_EQ(target.constraints[1].first, full({10, 30}));
  EXPECT_EQ(target.constraints[1].second, full({40}));
  EXPECT_FALSE(editor.setHandle(displayed({200})));  // nothing left after mapping: not sent
  EXPECT_EQ(target.constraints.size(), 2u);
}

TEST(ConstraintEditor, EachDragSendsItsOwnPosesAndEndsWithAStrokeEnd) {
  FakeTarget target;
  target.locked = true;
  ConstraintEditor editor(target);
  EXPECT_FALSE(editor.beginDrag());  // no handle
  ASSERT_TRUE(editor.setHandle(displayed({1})));
  EXPECT_FALSE(editor.dragTo(Eigen::Vector3d::UnitX(), Eigen::Matrix3d::Identity()));  // outside a drag

  ASSERT_TRUE(editor.beginDrag());
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(0.5 * EIGEN_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(1.0, 0.0, 0.0), quarter));
  EXPECT_EQ(target.strokeEnds, 0);
  editor.endDrag();
  EXPECT_FALSE(editor.dragging());
  EXPECT_EQ(target.strokeEnds, 1) << "the drag's end makes it an edit step";
  editor.endDrag();
  EXPECT_EQ(target.strokeEnds, 1) << "no drag, no stroke end";
  // the second drag's pose is its own: the host moves the handle from where the first drag left it
  ASSERT_TRUE(editor.beginDrag());
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(0.0, 2.0, 0.0), quarter));
  ASSERT_EQ(target.poses.size(), 2u);
  EXPECT_TRUE(target.poses[1].translation.isApprox(Eigen::Vector3d(0.0, 2.0, 0.0)));
  EXPECT_TRUE(target.poses[1].rotation.isApprox(quarter));
  EXPECT_EQ(target.constraints.size(), 1u) << "the same constraints: not sent again";

  target.refuse = true;
  EXPECT_FALSE(editor.dragTo(Eigen::Vector3d(5.0, 0.0, 0.0), quarter));
  target.refuse = false;

  target.locked = false;  // losing the lock ends the drag (the host ended the stroke with the tenure)
  editor.lockChanged(false);
  EXPECT_FALSE(editor.dragging());
  // Regaining it sends the constraints again; the host applies them from the shape as it is.
  target.locked = true;
  editor.lockChanged(true);
  EXPECT_EQ(target.constraints.size(), 2u);
}

TEST(ConstraintEditor, AdoptedConstraintsNeedNoNewSend) {
  FakeTarget target;
  target.locked = true;
  ConstraintEditor editor(target);
  const HostConstraints state{full({70}), full({80, 90})};
  editor.adopt(state, displayed({7}), displayed({8, 9}));
  EXPECT_EQ(editor.sent(), state);
  EXPECT_EQ(editor.anchors(), displayed({8, 9}));
  ASSERT_TRUE(editor.beginDrag());  // already sent: no new constraints
  EXPECT_TRUE(target.constraints.empty());
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Matrix3d::Identity()));
  EXPECT_TRUE(target.poses.back().translation.isApprox(Eigen::Vector3d(1.0, 0.0, 0.0)));
}

TEST(ConstraintEditor, UnchangedConstraintsAreNotSentAgain) {
  FakeTarget target;
  target.locked = true;
  ConstraintEditor editor(target);
  ASSERT_TRUE(editor.setSelection(displayed({1, 2}), displayed({5})));
  ASSERT_TRUE(editor.beginDrag());
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Matrix3d::Identity()));
  editor.endDrag();
  // A stroke that changed nothing (e.g. a click of the brush off the mesh) keeps the shape: nothing is sent.
  EXPECT_FALSE(editor.setSelection(displayed({2, 1}), displayed({5})));
  EXPECT_FALSE(editor.setHandle(displayed({1, 2})));
  EXPECT_EQ(target.constraints.size(), 1u);
  EXPECT_TRUE(editor.setAnchors(displayed({6})));  // a change is sent
  EXPECT_EQ(target.constraints.size(), 2u);
}

// Issue 15: switching resolution dropped the handle and anchors ("Paint a handle first"), and repainting reset the
// shape. The full ids are the truth: the new level shows them (the nearest displayed vertex where none stands for an
// id), nothing is sent, and the next drag goes on from the shape as it is.
TEST(ConstraintEditor, ALevelSwitchKeepsTheGroupsAndSendsNothing) {
  FakeTarget target;
  target.locked = true;
  ConstraintEditor editor(target);
  ASSERT_TRUE(editor.setSelection(displayed({3, 4}), displayed({9})));
  ASSERT_EQ(target.constraints.size(), 1u);
  EXPECT_EQ(target.constraints[0].first, full({30, 40}));
  ASSERT_TRUE(editor.beginDrag());
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Matrix3d::Identity()));
  editor.endDrag();

  target.step = 30;  // a coarser level: displayed d stands for full 30·d
  editor.levelChanged();
  EXPECT_EQ(editor.fullHandle(), full({30, 40}));
  EXPECT_EQ(editor.fullAnchors(), full({90}));
  EXPECT_EQ(editor.handle(), displayed({1}));   // 30 exactly; 40 (x = 4) nearest to displayed 1 (x = 3)
  EXPECT_EQ(editor.anchors(), displayed({3}));  // 90 exactly
  ASSERT_TRUE(editor.beginDrag()) << "no repainting needed";
  EXPECT_EQ(target.constraints.size(), 1u) << "the same constraints are not sent again (the shape would reset)";
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(0.0, 2.0, 0.0), Eigen::Matrix3d::Identity()));
  EXPECT_TRUE(target.poses.back().translation.isApprox(Eigen::Vector3d(0.0, 2.0, 0.0))) << "from the shape as it is";
  editor.endDrag();
  ASSERT_TRUE(editor.sent().has_value());
  EXPECT_EQ(editor.sent()->handle, full({30, 40}));
  EXPECT_EQ(editor.sent()->anchors, full({90}));

  target.step = 10;  // and back: the same displayed ids as painted
  editor.levelChanged();
  EXPECT_EQ(editor.handle(), displayed({3, 4}));
  EXPECT_EQ(editor.anchors(), displayed({9}));
  EXPECT_EQ(target.constraints.size(), 1u);
}

}  // namespace
}  // namespace sc::app
