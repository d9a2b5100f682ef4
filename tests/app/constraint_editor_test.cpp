// ConstraintEditor without a session: a fake EditTarget records what would be sent. Covers when constraints go out
// (now with the lock, else when it is granted), the id map and the handle-wins rule, each drag's poses sent as they
// are and ended by a stroke end (the host applies them from the current shape), a lost lock ending a drag, and the
// constraints a restored session adopts.

#include "app/gui/constraint_editor.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
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

/// Maps displayed id d to full id 10·d (a client's P, in miniature), drops d ≥ 100, and records the sends.
class FakeTarget final : public EditTarget {
 public:
  bool locked = false;
  bool refuse = false;
  std::vector<std::pair<FullVertexIds, FullVertexIds>> constraints;
  std::vector<spectral::HandleTransform> poses;
  int strokeEnds = 0;

  [[nodiscard]] bool canDrag() const override { return locked; }
  [[nodiscard]] FullVertexIds fullIds(const DisplayVertexIds& ids) const override {
    FullVertexIds out;
    for (const DisplayVertexId id : ids) {
      if (id.value < 100) out.emplace_back(10 * id.value);
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

TEST(ConstraintEditor, AdoptedConstraintsNeedNoNewSendAndClearForgetsTheIds) {
  FakeTarget target;
  target.locked = true;
  ConstraintEditor editor(target);
  const HostConstraints state{full({7}), full({8, 9})};
  editor.adopt(state, displayed({7}), displayed({8, 9}));
  EXPECT_EQ(editor.sent(), state);
  EXPECT_EQ(editor.anchors(), displayed({8, 9}));
  ASSERT_TRUE(editor.beginDrag());  // already sent: no new constraints
  EXPECT_TRUE(target.constraints.empty());
  ASSERT_TRUE(editor.dragTo(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Matrix3d::Identity()));
  EXPECT_TRUE(target.poses.back().translation.isApprox(Eigen::Vector3d(1.0, 0.0, 0.0)));

  editor.clear();
  EXPECT_TRUE(editor.handle().empty());
  EXPECT_TRUE(editor.anchors().empty());
  EXPECT_FALSE(editor.sent().has_value());
}

}  // namespace
}  // namespace sc::app
