#include "spectral/display_level.h"

#include "spectral/reconstruction_kernel.h"
#include "spectral/vertex_normals.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace sc::spectral {

namespace {

// The rest positions relative to the box centre, their box, the flat faces and the rest-shape normals.
void computeShape(const ResolutionLevel& level, DisplayGeometry& g) {
  const Eigen::Index n = level.restV.rows();
  if (n == 0) return;
  const Eigen::RowVector3d lo = level.restV.colwise().minCoeff();
  const Eigen::RowVector3d hi = level.restV.colwise().maxCoeff();
  g.origin = 0.5 * (lo + hi);
  g.rest.resize(static_cast<std::size_t>(3 * n));
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      g.rest[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(level.restV(i, k) - g.origin(k));
    }
  }
  g.lo = (lo - g.origin).transpose().cast<float>();
  g.hi = (hi - g.origin).transpose().cast<float>();
  bool inRange = true;
  g.indices.resize(static_cast<std::size_t>(3 * level.F.rows()));
  for (Eigen::Index f = 0; f < level.F.rows(); ++f) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      const int v = level.F(f, k);
      inRange = inRange && v >= 0 && v < n;
      g.indices[static_cast<std::size_t>(3 * f + k)] = static_cast<std::uint32_t>(v);
    }
  }
  g.normals.assign(g.rest.size(), 0.0f);
  if (inRange) vertexNormals(g.rest, g.indices, g.normals);
}

// max_i ‖K_i‖ and max_i |K_ik| of the dequantised K, read row by row from its int16 entries.
void computeBasisBounds(const QuantizedBasis& K, DisplayGeometry& g) {
  const Eigen::Index m = K.cols();
  std::vector<int> maxAbsQ(static_cast<std::size_t>(m), 0);
  float maxSquared = 0.0f;
  for (Eigen::Index i = 0; i < K.rows(); ++i) {
    const std::int16_t* row = K.Q.data() + i * m;  // row-major
    float squared = 0.0f;
    for (Eigen::Index k = 0; k < m; ++k) {
      const float value = static_cast<float>(row[k]) * K.scale(k);
      squared += value * value;
      maxAbsQ[static_cast<std::size_t>(k)] = std::max(maxAbsQ[static_cast<std::size_t>(k)], std::abs(int{row[k]}));
    }
    maxSquared = std::max(maxSquared, squared);
  }
  g.maxRowNorm = std::sqrt(maxSquared);
  g.maxAbsColumn.resize(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    g.maxAbsColumn(k) = static_cast<float>(maxAbsQ[static_cast<std::size_t>(k)]) * std::abs(K.scale(k));
  }
}

}  // namespace

SharedDisplayLevel makeDisplayLevel(ResolutionLevel level) {
  auto display = std::make_shared<DisplayLevel>();
  display->rest = interleavedPositions(level.restV);
  display->level = std::move(level);
  computeShape(display->level, display->geometry);
  computeBasisBounds(display->level.K, display->geometry);
  return display;
}

void reconstruct(const DisplayLevel& level, const DisplayFrame& frame, std::span<float> out, int threads) {
  assert(out.size() == level.rest.size());
  if (frame.Z.size() == 0) {
    std::copy(level.rest.begin(), level.rest.end(), out.begin());
    return;
  }
  reconstructInterleaved(level.level.K, level.rest, frame.Z, out, threads);
}

std::vector<float> reconstructed(const DisplayLevel& level, const DisplayFrame& frame, int threads) {
  std::vector<float> out(level.rest.size());
  reconstruct(level, frame, out, threads);
  return out;
}

}  // namespace sc::spectral
