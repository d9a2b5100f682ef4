// The row-band sweeps of block Lanczos against Eigen's plain products: same values on one and on several threads,
// with #V not a multiple of the band, and the same bits on every run with a given thread count.

#include "spectral/banded_products.h"

#include <gtest/gtest.h>

namespace sc::spectral {
namespace {

struct Operands {
  Eigen::MatrixXd q = Eigen::MatrixXd::Random(2777, 9);
  Eigen::MatrixXd w = Eigen::MatrixXd::Random(2777, 4);
  Eigen::VectorXd mass = Eigen::VectorXd::Random(2777).cwiseAbs().array() + 0.1;
};

double maxDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).cwiseAbs().maxCoeff(); }

class BandedProducts : public ::testing::TestWithParam<int> {};

TEST_P(BandedProducts, MatchPlainProducts) {
  const int threads = GetParam();
  const Operands x;
  EXPECT_LE(
      maxDifference(detail::massProjection(x.q, x.mass, x.w, threads), x.q.transpose() * x.mass.asDiagonal() * x.w),
      1e-11);
  EXPECT_LE(maxDifference(detail::massGram(x.w, x.mass, threads), x.w.transpose() * x.mass.asDiagonal() * x.w), 1e-11);

  const Eigen::MatrixXd h = Eigen::MatrixXd::Random(9, 4);
  Eigen::MatrixXd w = x.w;
  const Eigen::MatrixXd subtracted = x.w - x.q * h;
  const Eigen::MatrixXd gram = detail::subtractWithGram(w, x.q, h, x.mass, threads);
  EXPECT_LE(maxDifference(w, subtracted), 1e-12);
  EXPECT_LE(maxDifference(gram, subtracted.transpose() * x.mass.asDiagonal() * subtracted), 1e-10);

  const Eigen::MatrixXd r = Eigen::MatrixXd::Random(4, 4);
  w = x.w;
  const Eigen::MatrixXd multiplied = x.w * r;
  const Eigen::MatrixXd newGram = detail::multiplyWithGram(w, r, x.mass, threads);
  EXPECT_LE(maxDifference(w, multiplied), 1e-12);
  EXPECT_LE(maxDifference(newGram, multiplied.transpose() * x.mass.asDiagonal() * multiplied), 1e-10);
}

TEST_P(BandedProducts, ASubtractionAlsoGivesTheProjectionOfWhatItLeaves) {
  const int threads = GetParam();
  const Eigen::Index n = 9001;  // more than two of the subtraction's bands, not a multiple of one
  const Eigen::MatrixXd q = Eigen::MatrixXd::Random(n, 8);
  const Eigen::MatrixXd original = Eigen::MatrixXd::Random(n, 4);
  const Eigen::VectorXd mass = Eigen::VectorXd::Random(n).cwiseAbs().array() + 0.1;
  const Eigen::MatrixXd h = Eigen::MatrixXd::Random(8, 4);
  Eigen::MatrixXd w = original;
  const Eigen::MatrixXd subtracted = original - q * h;
  const detail::SubtractedBlock result = detail::subtractWithGramAndProjection(w, q, h, mass, threads);
  ASSERT_EQ(result.gram.rows(), 4);
  ASSERT_EQ(result.gram.cols(), 4);
  ASSERT_EQ(result.projection.rows(), 8);
  ASSERT_EQ(result.projection.cols(), 4);
  EXPECT_LE(maxDifference(w, subtracted), 1e-12);
  EXPECT_LE(maxDifference(result.gram, subtracted.transpose() * mass.asDiagonal() * subtracted), 1e-9);
  EXPECT_LE(maxDifference(result.projection, q.transpose() * mass.asDiagonal() * subtracted), 1e-9);
}

TEST_P(BandedProducts, AProductWrittenIntoColumnsOfAWiderMatrixAlsoGivesItsMassWeighting) {
  const int threads = GetParam();
  const Operands x;
  const Eigen::MatrixXd r = Eigen::MatrixXd::Random(4, 4);
  Eigen::MatrixXd basis = Eigen::MatrixXd::Constant(2777, 12, 7.0);
  Eigen::MatrixXd weighted(2777, 4);
  detail::multiplyInto(x.w, r, x.mass, basis.middleCols(5, 4), weighted, threads);
  const Eigen::MatrixXd product = x.w * r;
  EXPECT_LE(maxDifference(basis.middleCols(5, 4), product), 1e-12);
  EXPECT_LE(maxDifference(weighted, x.mass.asDiagonal() * product), 1e-12);
  EXPECT_TRUE((basis.leftCols(5).array() == 7.0).all() && (basis.rightCols(3).array() == 7.0).all())
      << "columns outside the target were written";
}

TEST_P(BandedProducts, SameBitsOnEveryRun) {
  const Operands x;
  const Eigen::MatrixXd first = detail::massProjection(x.q, x.mass, x.w, GetParam());
  for (int run = 0; run < 5; ++run) EXPECT_EQ(detail::massProjection(x.q, x.mass, x.w, GetParam()), first);
}

INSTANTIATE_TEST_SUITE_P(Threads, BandedProducts, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace sc::spectral
