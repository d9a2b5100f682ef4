#include "model/mesh_proxy.h"

#include "model/mesh_decimation.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

namespace sc::model {

Eigen::MatrixXi proxyTriangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetTriangles) {
  assert(targetTriangles >= 1 && "a proxy needs at least one triangle");
  if (F.rows() <= targetTriangles) return F;
  // Triangles per referenced vertex (about 2 on a closed mesh) turn the triangle target into a vertex target.
  std::vector<char> used(static_cast<std::size_t>(V.rows()), 0);
  for (Eigen::Index i = 0; i < F.size(); ++i) used[static_cast<std::size_t>(F(i))] = 1;
  const auto referenced = static_cast<double>(std::count(used.begin(), used.end(), 1));
  const double trianglesPerVertex = static_cast<double>(F.rows()) / std::max(1.0, referenced);
  const int target = std::max(3, static_cast<int>(std::lround(targetTriangles / trianglesPerVertex)));
  const DecimatedMesh low = decimateMesh(V, F, target);
  Eigen::MatrixXi proxy(low.F.rows(), 3);
  for (Eigen::Index i = 0; i < low.F.size(); ++i) proxy(i) = low.sourceVertices(low.F(i));
  return proxy;
}

}  // namespace sc::model
