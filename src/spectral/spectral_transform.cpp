#include "spectral/spectral_transform.h"

#include <cassert>

namespace sc::spectral {

Eigen::MatrixXd spectralCoefficients(const Eigen::MatrixXd& H, const Eigen::VectorXd& mass, const Eigen::MatrixXd& X) {
  assert(H.rows() == mass.size() && H.rows() == X.rows() && "H, mass and X must have #V rows");
  return H.transpose() * (mass.asDiagonal() * X);
}

Eigen::MatrixXd reconstruct(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& H, const Eigen::MatrixXd& Z) {
  assert(rest.rows() == H.rows() && H.cols() == Z.rows() && rest.cols() == Z.cols() && "shape mismatch");
  Eigen::MatrixXd X = rest;
  X.noalias() += H * Z;
  return X;
}

Eigen::MatrixXd reconstructFromRows(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& H, const Eigen::MatrixXd& Z,
                                    const std::vector<int>& rows) {
  assert(rest.rows() == H.rows() && H.cols() == Z.rows() && rest.cols() == Z.cols() && "shape mismatch");
  Eigen::MatrixXd X = rest;
  for (int k : rows) {
    assert(k >= 0 && k < Z.rows() && "row index out of range");
    X.noalias() += H.col(k) * Z.row(k);
  }
  return X;
}

}  // namespace sc::spectral
