#include "harmonic_host_model.h"

#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <utility>

namespace sc::session::testing {

std::shared_ptr<const HostModel> harmonicHostModel(const sc::testing::GeneratedMesh& mesh, int m) {
  auto model = std::make_shared<HostModel>();
  model->V = mesh.V;
  model->F = mesh.F;
  model->operators = spectral::laplaceOperators(mesh.V, mesh.F);
  spectral::BasisOptions options;
  options.m = m;
  spectral::BasisResult basis = spectral::manifoldHarmonicBasis(model->operators, options);
  EXPECT_TRUE(basis.ok()) << basis.message;
  model->basis = std::move(basis.basis);
  return model;
}

std::shared_ptr<const HostModel> incompressibleHostModel(const sc::testing::GeneratedMesh& mesh, int m, unsigned seed) {
  auto model = std::make_shared<HostModel>();
  model->V = mesh.V;
  model->F = mesh.F;
  model->operators = spectral::laplaceOperators(mesh.V, mesh.F);
  std::srand(seed);
  model->basis.vectors = Eigen::MatrixXd::Random(mesh.V.rows(), m);
  model->basis.eigenvalues = Eigen::VectorXd::LinSpaced(m, 0.0, 1.0);
  return model;
}

}  // namespace sc::session::testing
