#include "spectral/rigid_subspace.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>

namespace sc::spectral {
namespace {

constexpr int kEmbeddingDimensions = 10;
constexpr int kLloydIterations = 5;

Eigen::MatrixXd farthestPointCentres(const Eigen::MatrixXd& points, int clusters) {
  Eigen::MatrixXd centres(clusters, points.cols());
  Eigen::VectorXd distance = Eigen::VectorXd::Constant(points.rows(), std::numeric_limits<double>::infinity());
  Eigen::Index next = 0;
  for (int c = 0; c < clusters; ++c) {
    centres.row(c) = points.row(next);
    distance = distance.cwiseMin((points.rowwise() - points.row(next)).rowwise().squaredNorm());
    distance.maxCoeff(&next);
  }
  return centres;
}

/// Nearest centre of every row, with ‖p − c‖² = ‖p‖² − 2 p·c + ‖c‖² as one matrix product.
Eigen::VectorXi nearestCentres(const Eigen::MatrixXd& points, const Eigen::MatrixXd& centres) {
  Eigen::MatrixXd score = points * centres.transpose() * -2.0;
  score.rowwise() += centres.rowwise().squaredNorm().transpose();
  Eigen::VectorXi label(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i) score.row(i).minCoeff(&label(i));
  return label;
}

Eigen::Matrix3d closestRotation(const Eigen::Matrix3d& C) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  Eigen::Matrix3d R = U * svd.matrixV().transpose();
  if (R.determinant() < 0.0) {
    U.col(2) *= -1.0;
    R = U * svd.matrixV().transpose();
  }
  return R;
}

}  // namespace

Eigen::VectorXi kMeansClusters(const Eigen::MatrixXd& points, int clusters, int iterations) {
  clusters = std::clamp<int>(clusters, 1, static_cast<int>(points.rows()));
  Eigen::MatrixXd centres = farthestPointCentres(points, clusters);
  Eigen::VectorXi label = nearestCentres(points, centres);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(clusters, points.cols());
    Eigen::VectorXd counts = Eigen::VectorXd::Zero(clusters);
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      sums.row(label(i)) += points.row(i);
      counts(label(i)) += 1.0;
    }
    for (int c = 0; c < clusters; ++c)
      if (counts(c) > 0.0) centres.row(c) = sums.row(c) / counts(c);  // an empty cluster keeps its centre
    label = nearestCentres(points, centres);
  }
  return label;
}

RigidSubspace::RigidSubspace(const HarmonicBasis& basis, const LaplaceOperators& operators, const Eigen::MatrixXd& rest,
                             int clusters) {
  const Eigen::Index n = rest.rows();
  const Eigen::Index m = basis.size();
  // === step 1: clusters in the spectral embedding (geodesically sensible, unlike clustering positions)
  const int r = std::clamp<int>(clusters, 1, std::max<int>(1, static_cast<int>(n / 4)));
  const Eigen::MatrixXd embedding = basis.vectors.leftCols(std::min<Eigen::Index>(m, kEmbeddingDimensions));
  m_cluster = kMeansClusters(embedding, r, kLloydIterations);

  // === step 2: per-cluster Q_g and C⁰_g over every spoke (k → j) of the cotangent graph
  const Eigen::MatrixXd Ht = basis.vectors.transpose();  // column k = H_kᵀ, contiguous
  m_Q.assign(static_cast<std::size_t>(r), Eigen::MatrixX3d::Zero(m, 3));
  m_C0.assign(static_cast<std::size_t>(r), Eigen::Matrix3d::Zero());
  const SparseMatrix& S = operators.stiffness;
  for (Eigen::Index j = 0; j < S.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(S, j); it; ++it) {
      const Eigen::Index k = it.row();
      if (k == j) continue;
      const double w = -it.value();
      const Eigen::Vector3d edge = (rest.row(k) - rest.row(j)).transpose();
      const auto g = static_cast<std::size_t>(m_cluster(k));
      m_Q[g].noalias() += (0.5 * w) * (Ht.col(k) - Ht.col(j)) * edge.transpose();
      m_C0[g].noalias() += w * edge * edge.transpose();
    }
  m_restTerm = Eigen::MatrixXd::Zero(m, 3);
  for (const auto& Q : m_Q) m_restTerm += Q;
}

Eigen::MatrixXd RigidSubspace::rotationRightHandSide(const Eigen::MatrixXd& Z) const {
  Eigen::MatrixXd rhs = -m_restTerm;
  for (std::size_t g = 0; g < m_Q.size(); ++g) {
    const Eigen::Matrix3d C = m_C0[g] + 2.0 * Z.transpose() * m_Q[g];
    rhs.noalias() += m_Q[g] * closestRotation(C).transpose();
  }
  return rhs;
}

}  // namespace sc::spectral
