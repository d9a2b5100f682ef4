#pragma once
// Screen-space vertex picking for the viewport's selection brush, and the default anchor rule. Pure: no GL, no
// widget; MeshViewport feeds it its camera matrices and a depth image it read back.

#include <Eigen/Core>

#include <QMatrix4x4>
#include <QPointF>
#include <QSize>

#include <span>
#include <vector>

namespace sc::app {

/// A depth buffer read back from GL: window-space depth in [0, 1] (1 = far plane / nothing drawn), row-major with
/// row 0 at the *bottom* (glReadPixels order). width·height == depth.size().
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth;

  [[nodiscard]] bool empty() const { return depth.empty(); }
};

/// One vertex projected to the framebuffer: pixel coordinates with the origin at the top-left (Qt's convention,
/// pixel centres at +0.5) and whether the vertex is visible (in front of the near plane and not hidden).
struct ScreenPoint {
  float x = 0.0f;
  float y = 0.0f;
  bool visible = false;
};

/// Eye-space distance in front of the camera (a positive number) of a window-space depth d ∈ [0, 1] under a
/// perspective projection P (as built by QMatrix4x4::perspective: clip.w = −z_eye).
/// Returns +∞ for d ≥ 1 (nothing drawn there).
[[nodiscard]] float eyeDistanceFromWindowDepth(const QMatrix4x4& projection, float d);

/// Projects every vertex to the framebuffer and decides its visibility.
///
/// Visibility is a depth test against the *rendered* depth buffer (not a front-facing approximation): a vertex
/// is visible when it lies in front of the near plane, inside the framebuffer, and its eye distance is at most
/// the farthest rendered eye distance in the 3×3 pixel neighbourhood around it plus depthTolerance. Taking the
/// farthest neighbour keeps silhouette vertices and vertices on steep slopes visible; the tolerance absorbs
/// the difference between a vertex and the rasterised surface at a pixel centre.
/// @param[in] xyz             3·#V floats, x y z per vertex, in the space view maps from.
/// @param[in] view, projection  the matrices the depth image was rendered with.
/// @param[in] framebuffer     framebuffer size in pixels (device pixels).
/// @param[in] depth           read-back depth of that framebuffer, or nullptr / empty: then every vertex inside
///                            the framebuffer and in front of the camera counts as visible.
/// @param[in] depthTolerance  eye-space distance (scene units), e.g. 1% of the mesh's bounding-box diagonal.
/// @return #V screen points. Cost: O(#V).
[[nodiscard]] std::vector<ScreenPoint> projectToScreen(std::span<const float> xyz, const QMatrix4x4& view,
                                                       const QMatrix4x4& projection, QSize framebuffer,
                                                       const DepthImage* depth, float depthTolerance);

/// Indices (ascending) of the visible points within `radius` pixels (inclusive) of `centre`. Cost: O(#points).
[[nodiscard]] std::vector<int> visibleWithin(std::span<const ScreenPoint> points, QPointF centre, double radius);

/// One brush dab applied to a selection.
/// @param[in] selection  sorted, duplicate-free vertex indices.
/// @param[in] hits       sorted, duplicate-free indices under the brush.
/// @param[in] erase      false: the union selection ∪ hits; true: the difference selection \ hits.
/// @return sorted, duplicate-free result.
[[nodiscard]] std::vector<int> applyBrush(std::span<const int> selection, std::span<const int> hits, bool erase);

/// The default anchors for a handle: every vertex whose distance to the handle's centroid exceeds pct% of the
/// bounding-box diagonal of V, excluding the handle vertices themselves.
/// @param[in] V        #V by 3 positions.
/// @param[in] handles  indices into V (any order; duplicates allowed). Empty → no anchors.
/// @param[in] pct      percentage of the diagonal, ≥ 0 (40 leaves a generous free region around the handle).
/// @return sorted anchor indices. Cost: O(#V).
[[nodiscard]] std::vector<int> defaultAnchors(const Eigen::MatrixXd& V, std::span<const int> handles,
                                              double pct = 40.0);

}  // namespace sc::app
