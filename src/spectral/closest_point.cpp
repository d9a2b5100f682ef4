#include "spectral/closest_point.h"

#include "spectral/parallel_ranges.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cassert>
#include <vector>

namespace sc::spectral {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Eigen::Vector3d weights(double u, double v, double w) { return {u, v, w}; }

}  // namespace

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  // === vertex and edge regions (Ericson §5.1.5), in the order that makes the result unique
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return weights(1, 0, 0);
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return weights(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return weights(1 - t, t, 0);
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return weights(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return weights(1 - t, 0, t);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return weights(0, 1 - t, t);
  }
  // === interior: all of va, vb, vc > 0 here, so the weights are positive
  const double sum = va + vb + vc;
  const double v = vb / sum, w = vc / sum;
  return weights(1 - v - w, v, w);
}

struct ClosestPointQuery::Impl {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  std::vector<Triangle> triangles;
  Tree tree;

  void queryRange(const Eigen::MatrixXd& Q, std::ptrdiff_t begin, std::ptrdiff_t end, ClosestPoints& out) const {
    for (Eigen::Index q = begin; q < end; ++q) {
      const Eigen::Vector3d p = Q.row(q).transpose();
      const auto hit = tree.closest_point_and_primitive(Point(p.x(), p.y(), p.z()));
      const int f = static_cast<int>(hit.second - triangles.begin());
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Eigen::Vector3d w = closestPointOnTriangle(p, a, b, c);
      const Eigen::Vector3d x = w(0) * a + w(1) * b + w(2) * c;
      out.faces(q) = f;
      out.barycentric.row(q) = w.transpose();
      out.points.row(q) = x.transpose();
      out.distances(q) = (p - x).norm();
    }
  }
};

ClosestPointQuery::ClosestPointQuery(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
    : m_impl(std::make_unique<Impl>()) {
  assert(F.rows() >= 1 && F.cols() == 3 && V.cols() == 3 && "closest points need a non-empty triangle mesh");
  m_impl->V = V;
  m_impl->F = F;
  m_impl->triangles.reserve(static_cast<std::size_t>(F.rows()));
  const auto point = [&](Eigen::Index f, int k) { return Point(V(F(f, k), 0), V(F(f, k), 1), V(F(f, k), 2)); };
  for (Eigen::Index f = 0; f < F.rows(); ++f) m_impl->triangles.emplace_back(point(f, 0), point(f, 1), point(f, 2));
  // Build both the tree and its kd-tree now, so that concurrent queries never trigger a lazy build.
  m_impl->tree.insert(m_impl->triangles.cbegin(), m_impl->triangles.cend());
  m_impl->tree.build();
  m_impl->tree.accelerate_distance_queries();
}

ClosestPointQuery::~ClosestPointQuery() = default;
ClosestPointQuery::ClosestPointQuery(ClosestPointQuery&&) noexcept = default;
ClosestPointQuery& ClosestPointQuery::operator=(ClosestPointQuery&&) noexcept = default;

ClosestPoints ClosestPointQuery::query(const Eigen::MatrixXd& Q, int threads) const {
  assert(Q.cols() == 3 && "queries are #Q by 3");
  ClosestPoints out;
  out.faces.resize(Q.rows());
  out.barycentric.resize(Q.rows(), 3);
  out.points.resize(Q.rows(), 3);
  out.distances.resize(Q.rows());
  detail::parallelRanges(Q.rows(), threads,
                         [&](std::ptrdiff_t begin, std::ptrdiff_t end) { m_impl->queryRange(Q, begin, end, out); });
  return out;
}

ClosestPoints closestPoints(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& Q, int threads) {
  return ClosestPointQuery(V, F).query(Q, threads);
}

}  // namespace sc::spectral
