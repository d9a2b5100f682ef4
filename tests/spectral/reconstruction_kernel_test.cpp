#include "spectral/reconstruction_kernel.h"

#include <gtest/gtest.h>

#include <random>

namespace sc::spectral {
namespace {

struct KernelCase {
  RowMatrixXf K;
  Eigen::MatrixXd rest;
  Eigen::MatrixXf Z;
};

KernelCase randomCase(Eigen::Index n, Eigen::Index m, unsigned seed) {
  std::srand(seed);
  return {RowMatrixXf::Random(n, m), Eigen::MatrixXd::Random(n, 3), Eigen::MatrixXf::Random(m, 3)};
}

/// max |out − (X̂' + K Z)| with the reference summed in double, relative to max Σ_k |K_ik Z_kc|.
double relativeError(const KernelCase& c, const std::vector<float>& out) {
  const Eigen::MatrixXd K = c.K.cast<double>(), Z = c.Z.cast<double>();
  const Eigen::MatrixXd restF = c.rest.cast<float>().cast<double>();
  const Eigen::MatrixXd expected = restF + K * Z;
  const double scale = (K.cwiseAbs() * Z.cwiseAbs()).maxCoeff();
  double error = 0;
  for (Eigen::Index i = 0; i < expected.rows(); ++i)
    for (int k = 0; k < 3; ++k)
      error = std::max(error, std::abs(out[static_cast<std::size_t>(3 * i + k)] - expected(i, k)));
  return error / scale;
}

TEST(ReconstructionKernel, InterleavedPositionsAreXyzPerVertex) {
  Eigen::MatrixXd V(2, 3);
  V << 1, 2, 3, 4, 5, 6;
  EXPECT_EQ(interleavedPositions(V), (std::vector<float>{1, 2, 3, 4, 5, 6}));
}

TEST(ReconstructionKernel, EqualsDoubleReferenceForAnyBasisSizeAndThreadCount) {
  for (Eigen::Index m : {1, 5, 16, 37, 100}) {
    const KernelCase c = randomCase(1001, m, static_cast<unsigned>(m));
    const std::vector<float> rest = interleavedPositions(c.rest);
    for (int threads : {1, 2, 3}) {
      SCOPED_TRACE("m = " + std::to_string(m) + ", threads = " + std::to_string(threads));
      std::vector<float> out(rest.size(), -1.0f);
      reconstructInterleaved(c.K, rest, c.Z, out, threads);
      EXPECT_LT(relativeError(c, out), 1e-6);
    }
  }
}

TEST(ReconstructionKernel, OneAndTwoThreadsGiveIdenticalBuffers) {
  const KernelCase c = randomCase(20000, 100, 5);
  const std::vector<float> rest = interleavedPositions(c.rest);
  std::vector<float> one(rest.size()), two(rest.size());
  reconstructInterleaved(c.K, rest, c.Z, one, 1);
  reconstructInterleaved(c.K, rest, c.Z, two, 2);
  EXPECT_EQ(one, two);
}

TEST(ReconstructionKernel, ZeroCoefficientsGiveTheRestPositions) {
  const KernelCase c = randomCase(100, 30, 9);
  const std::vector<float> rest = interleavedPositions(c.rest);
  std::vector<float> out(rest.size());
  reconstructInterleaved(c.K, rest, Eigen::MatrixXf::Zero(30, 3), out);
  EXPECT_EQ(out, rest);
}

}  // namespace
}  // namespace sc::spectral
