#include "model/mesh_proxy.h"

#include "model/mesh_decimation.h"

#include <cassert>

namespace sc::model {

Eigen::MatrixXi proxyTriangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetTriangles) {
  assert(targetTriangles >= 1 && "a proxy needs at least one triangle");
  if (F.rows() <= targetTriangles) return F;
  const DecimatedMesh low = decimateToTriangles(V, F, targetTriangles);
  Eigen::MatrixXi proxy(low.F.rows(), 3);
  for (Eigen::Index i = 0; i < low.F.size(); ++i) proxy(i) = low.sourceVertices(low.F(i));
  return proxy;
}

}  // namespace sc::model
