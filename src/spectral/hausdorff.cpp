#include "spectral/hausdorff.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace sc::spectral {
namespace {

/// The interface nanoflann expects of a point cloud: rows of an n by 3 Eigen matrix.
struct RowCloud {
  const Eigen::MatrixXd& points;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(points.rows()); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return points(static_cast<Eigen::Index>(index), static_cast<Eigen::Index>(dim));
  }
  template <class Box>
  bool kdtree_get_bbox(Box& /*box*/) const {
    return false;  // let nanoflann compute it
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, RowCloud>, RowCloud, 3, std::size_t>;

/// Leaf size 10: nanoflann's default, a good balance of build and query cost for 3D points.
constexpr std::size_t kLeafSize = 10;

/// Relative width of the band of squared distances treated as ties of the nearest one (a few hundred ulps).
constexpr double kTieTolerance = 1e-13;

/// ‖q − B_j‖², summed in x, y, z order.
double squaredDistance(const Eigen::Vector3d& q, const Eigen::MatrixXd& B, Eigen::Index j) {
  const double dx = q(0) - B(j, 0);
  const double dy = q(1) - B(j, 1);
  const double dz = q(2) - B(j, 2);
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

struct NearestPointIndex::Tree {
  explicit Tree(const Eigen::MatrixXd& points)
      : cloud{points}, index(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize)) {}  // builds the tree
  RowCloud cloud;
  KdTree index;
};

NearestPointIndex::NearestPointIndex(const Eigen::MatrixXd& points) : m_tree(std::make_unique<Tree>(points)) {
  assert(points.cols() == 3 && "points must be n by 3");
}

NearestPointIndex::~NearestPointIndex() = default;

Eigen::Index NearestPointIndex::nearestIndex(const Eigen::Vector3d& q) const {
  if (m_tree->cloud.points.rows() == 0) return -1;
  std::size_t nearest = 0;
  double squared = 0.0;
  nanoflann::KNNResultSet<double, std::size_t> knn(1);
  knn.init(&nearest, &squared);
  m_tree->index.findNeighbors(knn, q.data(), nanoflann::SearchParams());
  return static_cast<Eigen::Index>(nearest);
}

double NearestPointIndex::nearestDistance(const Eigen::Vector3d& q) const {
  const Eigen::MatrixXd& B = m_tree->cloud.points;
  if (B.rows() == 0) return std::numeric_limits<double>::infinity();
  std::size_t nearest = 0;
  double squared = 0.0;
  nanoflann::KNNResultSet<double, std::size_t> knn(1);
  knn.init(&nearest, &squared);
  m_tree->index.findNeighbors(knn, q.data(), nanoflann::SearchParams());
  // Points tied with the nearest one up to rounding (common on symmetric meshes) are all re-measured with
  // squaredDistance(), so that the result is the exact minimum of that function, whichever tie nanoflann picked.
  const double slack = squared * kTieTolerance + std::numeric_limits<double>::min();
  std::vector<std::pair<std::size_t, double>> candidates;
  nanoflann::RadiusResultSet<double, std::size_t> ties(squared + slack, candidates);
  m_tree->index.findNeighbors(ties, q.data(), nanoflann::SearchParams());
  double best = squaredDistance(q, B, static_cast<Eigen::Index>(nearest));
  for (const auto& [index, ignored] : candidates)
    best = std::min(best, squaredDistance(q, B, static_cast<Eigen::Index>(index)));
  return std::sqrt(best);
}

double NearestPointIndex::maxNearestDistance(const Eigen::MatrixXd& A) const {
  assert(A.cols() == 3 && "A must be n by 3");
  double worst = 0.0;
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    worst = std::max(worst, nearestDistance(Eigen::Vector3d(A(i, 0), A(i, 1), A(i, 2))));
  return worst;
}

HausdorffDistance hausdorffDistance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  HausdorffDistance d;
  d.aToB = NearestPointIndex(B).maxNearestDistance(A);
  d.bToA = NearestPointIndex(A).maxNearestDistance(B);
  d.value = std::max(d.aToB, d.bToA);
  return d;
}

double maxVertexError(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  assert(X.rows() == Y.rows() && X.cols() == 3 && Y.cols() == 3 && "X and Y must both be n by 3");
  double worst = 0.0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    worst = std::max(worst, squaredDistance(Eigen::Vector3d(X(i, 0), X(i, 1), X(i, 2)), Y, i));
  return std::sqrt(worst);
}

double boundingBoxDiagonal(const Eigen::MatrixXd& V) {
  if (V.rows() == 0) return 0.0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

double percentOfDiagonal(double distance, double diagonal) {
  if (!(diagonal > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return 100.0 * distance / diagonal;
}

}  // namespace sc::spectral
