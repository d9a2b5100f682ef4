#include "spectral/surface_distance.h"

#include "spectral/closest_point.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sc::spectral {
namespace {

DistanceStats statsOf(const Eigen::VectorXd& d) {
  if (d.size() == 0) return {};
  return {d.maxCoeff(), d.mean(), std::sqrt(d.squaredNorm() / static_cast<double>(d.size()))};
}

DistanceStats scaled(const DistanceStats& s, double factor) {
  return {s.max * factor, s.mean * factor, s.rms * factor};
}

}  // namespace

SurfaceDistance pointToSurfaceDistance(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                       const Eigen::MatrixXi& F, double diagonal, int threads) {
  assert(diagonal > 0 && "normalise by a positive length");
  SurfaceDistance out;
  out.raw = statsOf(closestPoints(V, F, points, threads).distances);
  out.relative = scaled(out.raw, 1.0 / diagonal);
  return out;
}

SymmetricSurfaceDistance symmetricSurfaceDistance(const Eigen::MatrixXd& VA, const Eigen::MatrixXi& FA,
                                                  const Eigen::MatrixXd& VB, const Eigen::MatrixXi& FB, double diagonal,
                                                  int threads) {
  SymmetricSurfaceDistance out;
  out.aToB = pointToSurfaceDistance(VA, VB, FB, diagonal, threads);
  out.bToA = pointToSurfaceDistance(VB, VA, FA, diagonal, threads);
  out.maxRaw = std::max(out.aToB.raw.max, out.bToA.raw.max);
  out.maxRelative = out.maxRaw / diagonal;
  return out;
}

}  // namespace sc::spectral
