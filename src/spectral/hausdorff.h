#pragma once
// Shape distortion metrics (shared/design/spectral.md §7): vertex-set Hausdorff distance with a kd-tree, the cheap
// same-connectivity max vertex error, and normalisation by the rest bounding-box diagonal.

#include <Eigen/Core>

#include <memory>

namespace sc::spectral {

/// Symmetric vertex-set Hausdorff distance and its two one-sided parts, in model units.
struct HausdorffDistance {
  double value = 0.0;  ///< max(aToB, bToA).
  double aToB = 0.0;   ///< max_{a∈A} min_{b∈B} ‖a − b‖: how far A strays from B.
  double bToA = 0.0;   ///< max_{b∈B} min_{a∈A} ‖a − b‖.
};

/// Nearest-point queries against one fixed point set (a kd-tree built once, nanoflann): the stateful tier of
/// hausdorffDistance(), for measuring many point sets against the same reference (e.g. the rest or server mesh).
class NearestPointIndex {
 public:
  /// Builds the kd-tree. Cost: O(n log n).
  /// @param[in] points  n by 3 reference set B; kept by reference: must outlive the index and stay unchanged.
  explicit NearestPointIndex(const Eigen::MatrixXd& points);
  ~NearestPointIndex();
  NearestPointIndex(const NearestPointIndex&) = delete;
  NearestPointIndex& operator=(const NearestPointIndex&) = delete;

  /// Euclidean distance from q to the nearest reference point; +∞ if the reference set is empty. Thread-safe.
  /// Cost: O(log n) expected.
  double nearestDistance(const Eigen::Vector3d& q) const;

  /// Row of a reference point nearest to q (one of them on ties); −1 if the reference set is empty. Thread-safe.
  /// Cost: O(log n) expected.
  Eigen::Index nearestIndex(const Eigen::Vector3d& q) const;

  /// One-sided Hausdorff distance max_{a∈A} min_{b∈B} ‖a − b‖ of the rows of A (n' by 3) to the reference set B.
  /// 0 if A is empty; +∞ if A is not empty and B is. Cost: O(n' log n).
  double maxNearestDistance(const Eigen::MatrixXd& A) const;

 private:
  struct Tree;  // nanoflann types stay out of this header
  std::unique_ptr<Tree> m_tree;
};

/// Vertex-set Hausdorff distance d_H(A, B) = max(max_a min_b ‖a−b‖, max_b min_a ‖a−b‖) between the rows of A
/// (n by 3) and B (n' by 3). Point sets only: connectivity and faces are ignored, so across resolutions it also
/// measures vertex spacing (design note §7, pitfall 14). Both empty: 0; exactly one empty: +∞.
/// Distances are exact Euclidean distances (the kd-tree only prunes; no approximation).
/// Cost: O((n + n') log(n + n')) time, O(n + n') memory for the two trees.
HausdorffDistance hausdorffDistance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);

/// Same-connectivity max vertex error max_i ‖x_i − x'_i‖ between corresponding rows of X and Y (both n by 3).
/// An upper bound of hausdorffDistance(X, Y) (each x_i has y_i at that distance, and vice versa). 0 when n = 0.
/// \pre X and Y have the same shape. Cost: O(n).
double maxVertexError(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y);

/// Length of the diagonal of the axis-aligned bounding box of the rows of V (n by 3); 0 when n = 0.
/// Use the rest full-resolution mesh, so that normalised values do not drift with the pose. Cost: O(n).
double boundingBoxDiagonal(const Eigen::MatrixXd& V);

/// A distance as a percentage of a bounding-box diagonal: 100 · distance / diagonal. NaN if diagonal ≤ 0.
double percentOfDiagonal(double distance, double diagonal);

}  // namespace sc::spectral
