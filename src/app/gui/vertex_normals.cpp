#include "app/gui/vertex_normals.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sc::app {

Eigen::MatrixXd vertexNormals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  assert(V.cols() == 3 && F.cols() == 3 && "V and F must be #V by 3 and #F by 3");
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(V.rows(), 3);
  // === step 1: accumulate area-weighted face normals on the corners.
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int i0 = F(f, 0);
    const int i1 = F(f, 1);
    const int i2 = F(f, 2);
    assert(i0 >= 0 && i1 >= 0 && i2 >= 0 && i0 < V.rows() && i1 < V.rows() && i2 < V.rows() &&
           "face index out of range");
    const Eigen::RowVector3d p0 = V.row(i0);
    const Eigen::RowVector3d e1 = V.row(i1) - p0;
    const Eigen::RowVector3d e2 = V.row(i2) - p0;
    const Eigen::RowVector3d n = e1.cross(e2);
    N.row(i0) += n;
    N.row(i1) += n;
    N.row(i2) += n;
  }
  // === step 2: normalise, leaving degenerate neighbourhoods at zero.
  for (Eigen::Index v = 0; v < N.rows(); ++v) {
    const double length = N.row(v).norm();
    if (length > 0.0) {
      N.row(v) /= length;
    }
  }
  return N;
}

}  // namespace sc::app
