#include "app/gui/viewport/vertex_arrays.h"

#include <algorithm>
#include <limits>

namespace sc::app {

std::vector<std::uint32_t> flatIndices(const Eigen::MatrixXi& F) {
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(F.size()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (Eigen::Index c = 0; c < F.cols(); ++c) {
      indices[static_cast<std::size_t>(F.cols() * f + c)] = static_cast<std::uint32_t>(F(f, c));
    }
  }
  return indices;
}

void shifted(std::span<const float> xyz, const Eigen::RowVector3d& shift, std::vector<float>& out) {
  const float by[3] = {static_cast<float>(shift(0)), static_cast<float>(shift(1)), static_cast<float>(shift(2))};
  out.resize(xyz.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    out[i] = xyz[i] + by[i % 3];
  }
}

std::pair<QVector3D, QVector3D> boundsOf(std::span<const float> p) {
  constexpr float kMax = std::numeric_limits<float>::max();
  QVector3D lo(kMax, kMax, kMax);
  QVector3D hi = -lo;
  for (std::size_t i = 0; i + 2 < p.size(); i += 3) {
    lo = QVector3D(std::min(lo.x(), p[i]), std::min(lo.y(), p[i + 1]), std::min(lo.z(), p[i + 2]));
    hi = QVector3D(std::max(hi.x(), p[i]), std::max(hi.y(), p[i + 1]), std::max(hi.z(), p[i + 2]));
  }
  return {lo, hi};
}

}  // namespace sc::app
