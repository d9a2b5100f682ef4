#include "app/gui/vertex_picking.h"

#include <QVector4D>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
#include <limits>

namespace sc::app {

float eyeDistanceFromWindowDepth(const QMatrix4x4& projection, float d) {
  if (d >= 1.0f) {
    return std::numeric_limits<float>::infinity();
  }
  // clip.z = P22·z + P23 and clip.w = −z, so ndc = (P22·z + P23)/(−z) and z = −P23 / (ndc + P22).
  const float ndc = 2.0f * d - 1.0f;
  const float zEye = -projection(2, 3) / (ndc + projection(2, 2));
  return -zEye;
}

namespace {

// Farthest rendered eye distance in the 3×3 neighbourhood of pixel (px, rowFromBottom).
float farthestAround(const DepthImage& image, const QMatrix4x4& projection, int px, int row) {
  float farthest = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int x = std::clamp(px + dx, 0, image.width - 1);
      const int y = std::clamp(row + dy, 0, image.height - 1);
      const float d =
          image
              .depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)];
      farthest = std::max(farthest, eyeDistanceFromWindowDepth(projection, d));
    }
  }
  return farthest;
}

}  // namespace

std::vector<ScreenPoint> projectToScreen(std::span<const float> xyz, const QMatrix4x4& view,
                                         const QMatrix4x4& projection, QSize framebuffer, const DepthImage* depth,
                                         float depthTolerance) {
  assert(xyz.size() % 3 == 0 && "xyz holds 3 floats per vertex");
  const bool useDepth = depth != nullptr && !depth->empty() && depth->width == framebuffer.width() &&
                        depth->height == framebuffer.height();
  const auto w = static_cast<float>(framebuffer.width());
  const auto h = static_cast<float>(framebuffer.height());
  std::vector<ScreenPoint> points(xyz.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const QVector4D eye = view.map(QVector4D(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 1.0f));
    const QVector4D clip = projection.map(eye);
    ScreenPoint& p = points[i];
    if (clip.w() <= 0.0f) {
      continue;  // behind the eye
    }
    p.x = (clip.x() / clip.w() * 0.5f + 0.5f) * w;
    p.y = (0.5f - clip.y() / clip.w() * 0.5f) * h;
    const bool inside = p.x >= 0.0f && p.y >= 0.0f && p.x < w && p.y < h && std::abs(clip.z()) <= clip.w();
    if (!inside) {
      continue;
    }
    p.visible = true;
    if (useDepth) {
      const int px = static_cast<int>(p.x);
      const int row = depth->height - 1 - static_cast<int>(p.y);
      p.visible = -eye.z() <= farthestAround(*depth, projection, px, row) + depthTolerance;
    }
  }
  return points;
}

std::vector<int> visibleWithin(std::span<const ScreenPoint> points, QPointF centre, double radius) {
  std::vector<int> hits;
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ScreenPoint& p = points[i];
    const double dx = p.x - centre.x();
    const double dy = p.y - centre.y();
    if (p.visible && dx * dx + dy * dy <= r2) {
      hits.push_back(static_cast<int>(i));
    }
  }
  return hits;
}

std::vector<int> applyBrush(std::span<const int> selection, std::span<const int> hits, bool erase) {
  std::vector<int> result;
  result.reserve(selection.size() + (erase ? 0 : hits.size()));
  if (erase) {
    std::set_difference(selection.begin(), selection.end(), hits.begin(), hits.end(), std::back_inserter(result));
  } else {
    std::set_union(selection.begin(), selection.end(), hits.begin(), hits.end(), std::back_inserter(result));
  }
  return result;
}

std::vector<int> defaultAnchors(const Eigen::MatrixXd& V, std::span<const int> handles, double pct) {
  assert(V.cols() == 3 && pct >= 0.0 && "V is #V by 3 and pct is non-negative");
  if (handles.empty() || V.rows() == 0) {
    return {};
  }
  // === step 1: the handle's centroid and the free radius.
  Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
  std::vector<char> isHandle(static_cast<std::size_t>(V.rows()), 0);
  for (const int h : handles) {
    assert(h >= 0 && h < V.rows() && "handle index out of range");
    centroid += V.row(h);
    isHandle[static_cast<std::size_t>(h)] = 1;
  }
  centroid /= static_cast<double>(handles.size());
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const double radius = pct / 100.0 * diagonal;

  // === step 2: everything beyond it is anchored.
  std::vector<int> anchors;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (isHandle[static_cast<std::size_t>(i)] == 0 && (V.row(i) - centroid).norm() > radius) {
      anchors.push_back(static_cast<int>(i));
    }
  }
  return anchors;
}

}  // namespace sc::app
