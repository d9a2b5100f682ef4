#include "spectral/vertex_order.h"

#include "spectral/parallel_ranges.h"

#include <cassert>

namespace sc::spectral::detail {

Eigen::MatrixXd VertexOrder::gather(const Eigen::MatrixXd& x) const {
  assert(x.rows() == size());
  Eigen::MatrixXd result(x.rows(), x.cols());
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    for (Eigen::Index i = 0; i < size(); ++i) result(i, c) = x(m_order[static_cast<std::size_t>(i)], c);
  }
  return result;
}

void VertexOrder::scatterInPlace(Eigen::MatrixXd& x, int threads) const {
  assert(x.rows() == size());
  parallelRanges(x.cols(), threads, [&](std::ptrdiff_t first, std::ptrdiff_t last) {
    Eigen::VectorXd buffer(size());
    for (Eigen::Index c = first; c < last; ++c) {
      buffer = x.col(c);
      for (Eigen::Index i = 0; i < size(); ++i) x(m_order[static_cast<std::size_t>(i)], c) = buffer[i];
    }
  });
}

}  // namespace sc::spectral::detail
