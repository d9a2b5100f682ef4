#pragma once
// Exact closest points on a triangle mesh for many query points (CGAL AABB tree, kept out of this header).

#include <Eigen/Core>

#include <memory>

namespace sc::spectral {

/// Closest points of a batch of queries; row q of every member belongs to query q.
struct ClosestPoints {
  Eigen::VectorXi faces;        ///< #Q face index (row of F) holding the closest point.
  Eigen::MatrixXd barycentric;  ///< #Q by 3 weights of that face's corners F(f,0..2): each ≥ 0, rows sum to 1.
  Eigen::MatrixXd points;       ///< #Q by 3 closest points, Σ_k barycentric(q,k)·V(F(f,k)).
  Eigen::VectorXd distances;    ///< #Q Euclidean distances ‖query − point‖.
};

/// Closest point of the triangle (a, b, c) to p, as barycentric weights (≥ 0, sum 1) of a, b, c.
///
/// Ericson's region test (Real-Time Collision Detection §5.1.5): the weights come out non-negative and summing
/// to 1 by construction, also on degenerate (needle, cap or zero-area) triangles.
/// Cost: O(1), a few dozen flops.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

/// A triangle mesh prepared for closest-point queries: the AABB tree is built once, queries are read-only.
///
/// The tree (CGAL::AABB_tree on Simple_cartesian<double>, with its distance-acceleration kd-tree) finds the
/// closest face; the weights, point and distance are then recomputed from that face by closestPointOnTriangle(),
/// so they are exact in double up to round-off. When several faces are equally close, any of them may come back.
/// Queries on one instance may run concurrently (the tree is fully built by the constructor).
class ClosestPointQuery {
 public:
  /// @param[in] V  #V by 3 positions (finite); copied, the caller's matrix may go away.
  /// @param[in] F  #F by 3 indices into V, #F ≥ 1.
  /// Cost: O(#F log #F) time, O(#F) memory (about 150 bytes per face).
  ClosestPointQuery(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  ~ClosestPointQuery();
  ClosestPointQuery(const ClosestPointQuery&) = delete;
  ClosestPointQuery& operator=(const ClosestPointQuery&) = delete;
  ClosestPointQuery(ClosestPointQuery&&) noexcept;
  ClosestPointQuery& operator=(ClosestPointQuery&&) noexcept;

  /// Closest points of every row of Q.
  /// @param[in] Q  #Q by 3 query points (finite).
  /// @param[in] threads  number of std::threads to split the queries over (≥ 1; 1 runs on the caller's thread).
  /// Cost: about O(log #F) per query (typically a few µs).
  ClosestPoints query(const Eigen::MatrixXd& Q, int threads = 1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

/// One-off: ClosestPointQuery(V, F).query(Q, threads). Cost: tree build plus the queries.
ClosestPoints closestPoints(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& Q,
                            int threads = 1);

}  // namespace sc::spectral
