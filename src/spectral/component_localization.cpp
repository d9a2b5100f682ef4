#include "spectral/component_localization.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <set>

namespace sc::spectral {
namespace {

/// Localises columns [first, first + size) of H; returns false (H unchanged) if the masked directions do not
/// exactly fill the cluster.
bool localizeCluster(const Eigen::VectorXi& component, int components, const Eigen::VectorXd& mass, Eigen::MatrixXd& H,
                     Eigen::Index first, Eigen::Index size) {
  const Eigen::MatrixXd cluster = H.middleCols(first, size);
  Eigen::MatrixXd localized(H.rows(), size);
  Eigen::Index found = 0;
  for (int c = 0; c < components; ++c) {
    const Eigen::VectorXd maskedMass = (component.array() == c).select(mass, 0.0);
    const Eigen::MatrixXd gram = cluster.transpose() * (maskedMass.asDiagonal() * cluster);
    if (gram.trace() < 0.5) continue;  // the cluster does not reach this component
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
    for (Eigen::Index k = size - 1; k >= 0 && eig.eigenvalues()(k) > 0.5; --k) {
      if (found == size) return false;
      const Eigen::VectorXd v = cluster * eig.eigenvectors().col(k) / std::sqrt(eig.eigenvalues()(k));
      localized.col(found++) = (component.array() == c).select(v, 0.0);
    }
  }
  if (found != size) return false;
  H.middleCols(first, size) = localized;
  return true;
}

}  // namespace

void localizeToComponents(const Eigen::VectorXi& component, int components, const Eigen::VectorXd& mass,
                          const Eigen::VectorXd& eigenvalues, Eigen::MatrixXd& H, double tolerance) {
  if (components < 2 || eigenvalues.size() == 0) return;
  const double gap = tolerance * std::max(eigenvalues.cwiseAbs().maxCoeff(), 1e-300);
  for (Eigen::Index first = 0; first < eigenvalues.size();) {
    Eigen::Index size = 1;
    while (first + size < eigenvalues.size() && eigenvalues(first + size) - eigenvalues(first + size - 1) <= gap)
      ++size;
    std::set<int> touched;
    for (Eigen::Index k = first; k < first + size; ++k)
      for (Eigen::Index i = 0; i < H.rows(); ++i)
        if (H(i, k) != 0.0) touched.insert(component(i));
    if (size > 1 && touched.size() > 1) localizeCluster(component, components, mass, H, first, size);
    first += size;
  }
}

}  // namespace sc::spectral
