// VertexOrder (gathering #V-vectors into a factor's order and back) and ShiftInvertOperator's solves in that order.

#include "spectral/vertex_order.h"
#include "spectral/laplace_operators.h"
#include "spectral/shift_invert_operator.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

namespace sc::spectral::detail {
namespace {

TEST(VertexOrder, GatherPutsRowOrderIAtIAndScatterUndoesItOnAnyNumberOfThreads) {
  std::vector<int> order(1001);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  const VertexOrder vertexOrder(order);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(1001, 5);
  const Eigen::MatrixXd gathered = vertexOrder.gather(x);
  for (Eigen::Index i = 0; i < x.rows(); ++i) EXPECT_EQ(gathered.row(i), x.row(order[static_cast<std::size_t>(i)]));
  for (int threads : {1, 2, 3, 8}) {
    Eigen::MatrixXd back = gathered;
    vertexOrder.scatterInPlace(back, threads);
    EXPECT_EQ(back, x) << threads << " threads";
  }
}

TEST(ShiftInvertOperator, ASolveInTheFactorsOrderIsTheSolveGathered) {
  const auto mesh = testing::torus(24, 12);
  const LaplaceOperators ops = laplaceOperators(mesh.V, mesh.F);
  ShiftInvertOperator op(ops.stiffness, ops.mass, {});
  op.set_shift(-4.0 * std::numbers::pi / ops.totalArea);
  std::vector<int> order(op.factorOrder().begin(), op.factorOrder().end());
  ASSERT_EQ(static_cast<Eigen::Index>(order.size()), ops.mass.size());
  std::sort(order.begin(), order.end());
  for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], static_cast<int>(i)) << "not a permutation";
  const VertexOrder vertexOrder(op.factorOrder());
  ASSERT_FALSE(std::is_sorted(op.factorOrder().begin(), op.factorOrder().end())) << "the identity tests nothing";
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(ops.mass.size(), 4);
  for (int threads : {1, 2}) {
    op.setSolveThreads(threads);
    Eigen::MatrixXd plain, ordered;
    op.solve(x, plain);
    op.solveInFactorOrder(vertexOrder.gather(x), ordered);
    EXPECT_LE((ordered - vertexOrder.gather(plain)).norm(), 1e-12 * plain.norm()) << threads << " threads";
  }
  EXPECT_EQ(op.solveCount(), 16);
}

}  // namespace
}  // namespace sc::spectral::detail
