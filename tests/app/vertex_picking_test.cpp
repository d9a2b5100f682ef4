// Tests for src/app/gui/vertex_picking.cpp: projection, depth visibility, brush set algebra and default anchors
// (pure: no GL, no display).

#include "app/gui/vertex_picking.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

// A camera at (0, 0, 5) looking at the origin, 30° vertical field of view, on a 100 × 100 framebuffer.
struct PickingCamera {
  QMatrix4x4 view;
  QMatrix4x4 projection;
  QSize size{100, 100};
  PickingCamera() {
    view.lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
    projection.perspective(30.0f, 1.0f, 1.0f, 10.0f);
  }
  // Window depth [0, 1] of a point at eye distance e.
  [[nodiscard]] float windowDepth(float e) const {
    const float ndc = (projection(2, 2) * -e + projection(2, 3)) / e;
    return 0.5f * ndc + 0.5f;
  }
};

}  // namespace

TEST(VertexPicking, EyeDistanceInvertsTheProjection) {
  const PickingCamera camera;
  for (const float e : {1.5f, 5.0f, 9.0f}) {
    EXPECT_NEAR(sc::app::eyeDistanceFromWindowDepth(camera.projection, camera.windowDepth(e)), e, 1e-3f * e);
  }
  EXPECT_TRUE(std::isinf(sc::app::eyeDistanceFromWindowDepth(camera.projection, 1.0f))) << "cleared depth";
}

TEST(VertexPicking, ProjectsToPixelsWithTheOriginTopLeft) {
  const PickingCamera camera;
  const std::vector<float> xyz = {0, 0, 0, /**/ 0.5f, 0.5f, 0, /**/ 0, 0, 6 /* behind the eye */};
  const auto points = sc::app::projectToScreen(xyz, camera.view, camera.projection, camera.size, nullptr, 0.0f);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_FLOAT_EQ(points[0].x, 50.0f);
  EXPECT_FLOAT_EQ(points[0].y, 50.0f);
  EXPECT_TRUE(points[0].visible);
  EXPECT_GT(points[1].x, 50.0f) << "+x is to the right";
  EXPECT_LT(points[1].y, 50.0f) << "+y is up, i.e. a smaller row";
  EXPECT_FALSE(points[2].visible) << "behind the eye";
}

TEST(VertexPicking, DepthImageHidesPointsBehindTheSurface) {
  const PickingCamera camera;
  // A wall at eye distance 5 (z = 0) covering the whole framebuffer.
  sc::app::DepthImage wall{100, 100, std::vector<float>(100 * 100, camera.windowDepth(5.0f))};
  const std::vector<float> xyz = {0, 0, 0 /* on the wall */, 0, 0, -1 /* behind */, 0, 0, 1 /* in front */};
  const auto points = sc::app::projectToScreen(xyz, camera.view, camera.projection, camera.size, &wall, 0.05f);
  EXPECT_TRUE(points[0].visible);
  EXPECT_FALSE(points[1].visible);
  EXPECT_TRUE(points[2].visible);
  // Nothing drawn near a point (a silhouette): visible whatever its depth.
  for (int x = 45; x < 56; ++x) {
    wall.depth[50 * 100 + x] = 1.0f;
  }
  EXPECT_TRUE(sc::app::projectToScreen(xyz, camera.view, camera.projection, camera.size, &wall, 0.05f)[1].visible);
}

TEST(VertexPicking, VisibleWithinIsAnInclusiveDiscOverVisiblePoints) {
  const std::vector<sc::app::ScreenPoint> points = {
      {10, 10, true}, {13, 14, true} /* distance 5 */, {10, 11, false}, {20, 10, true}};
  EXPECT_EQ(sc::app::visibleWithin(points, {10, 10}, 5.0), (std::vector<int>{0, 1}));
  EXPECT_TRUE(sc::app::visibleWithin(points, {50, 50}, 5.0).empty());
}

TEST(VertexPicking, BrushUnionsAndErases) {
  const std::vector<int> selection = {1, 3, 5};
  EXPECT_EQ(sc::app::applyBrush(selection, std::vector<int>{2, 3, 9}, false), (std::vector<int>{1, 2, 3, 5, 9}));
  EXPECT_EQ(sc::app::applyBrush(selection, std::vector<int>{3, 4, 5}, true), (std::vector<int>{1}));
  EXPECT_TRUE(sc::app::applyBrush({}, std::vector<int>{1}, true).empty());
}

TEST(VertexPicking, DefaultAnchorsAreFarFromTheHandleCentroid) {
  // 11 × 11 vertex grid on [0,1]²; the diagonal is √2, so 40% is 0.566.
  const auto grid = sc::testing::grid(10, 10);
  const std::vector<int> handles = {0};  // the corner (0, 0)
  const std::vector<int> anchors = sc::app::defaultAnchors(grid.V, handles, 40.0);
  ASSERT_FALSE(anchors.empty());
  const double radius = 0.4 * std::sqrt(2.0);
  for (Eigen::Index i = 0; i < grid.V.rows(); ++i) {
    const bool far = grid.V.row(i).head<2>().norm() > radius;
    EXPECT_EQ(std::binary_search(anchors.begin(), anchors.end(), static_cast<int>(i)), far) << "vertex " << i;
  }
  EXPECT_TRUE(std::is_sorted(anchors.begin(), anchors.end()));
  EXPECT_TRUE(sc::app::defaultAnchors(grid.V, {}, 40.0).empty()) << "no handle, no anchors";
  const std::vector<int> all = {0, 1};  // centroid (0.05, 0) is no vertex
  EXPECT_EQ(sc::app::defaultAnchors(grid.V, all, 0.0).size(), static_cast<std::size_t>(grid.V.rows() - 2))
      << "handles are never anchors";
}
