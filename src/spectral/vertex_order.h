#pragma once
// VertexOrder: vectors over a mesh's vertices gathered into another order (a sparse factor's fill-reducing order)
// and scattered back. Internal to src/spectral (block_lanczos.cpp keeps its Krylov basis in the factor's order).

#include <Eigen/Core>

#include <span>

namespace sc::spectral::detail {

/// A permutation of the #V vertices, `order[i]` = the vertex at position i; viewed, not copied (the caller keeps
/// it alive, e.g. ShiftInvertOperator::factorOrder()).
class VertexOrder {
 public:
  explicit VertexOrder(std::span<const int> order) : m_order(order) {}

  Eigen::Index size() const { return static_cast<Eigen::Index>(m_order.size()); }

  /// X's rows in this order: row i of the result is row order[i] of X (#V rows). Cost: one random read per entry.
  Eigen::MatrixXd gather(const Eigen::MatrixXd& x) const;

  /// The inverse of gather(), in place: row order[i] of X becomes what row i was. Column by column through a buffer
  /// of #V doubles per thread (`threads` split the columns), so that no second #V × cols matrix is held (the Ritz
  /// vectors are 800 MB at 1M vertices and m = 100). Cost: a copy and a random write per entry.
  void scatterInPlace(Eigen::MatrixXd& x, int threads) const;

 private:
  std::span<const int> m_order;
};

}  // namespace sc::spectral::detail
