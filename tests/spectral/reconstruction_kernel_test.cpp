#include "spectral/reconstruction_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

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

constexpr KernelLoop kLoops[] = {KernelLoop::Fastest, KernelLoop::Portable};

std::string loopName(KernelLoop loop) { return loop == KernelLoop::Fastest ? "fastest" : "portable"; }

// Sizes around the fast loop's blocks: m below, at and past multiples of its 8-column chunks, n' not a multiple of
// its 4-row passes (the leftover rows go through a padded copy).
TEST(ReconstructionKernel, EqualsDoubleReferenceForAnyBasisSizeAndThreadCount) {
  for (const Eigen::Index m : {1, 5, 7, 8, 9, 16, 37, 100}) {
    for (const Eigen::Index n : {1, 3, 1001}) {
      const KernelCase c = randomCase(n, m, static_cast<unsigned>(m + n));
      const std::vector<float> rest = interleavedPositions(c.rest);
      for (const KernelLoop loop : kLoops)
        for (const int threads : {1, 2, 3}) {
          SCOPED_TRACE("m = " + std::to_string(m) + ", n = " + std::to_string(n) + ", " + loopName(loop) +
                       ", threads = " + std::to_string(threads));
          std::vector<float> out(rest.size(), -1.0f);
          reconstructInterleaved(c.K, rest, c.Z, out, threads, loop);
          EXPECT_LT(relativeError(c, out), 1e-6);
        }
    }
  }
}

// Thread chunks split the rows at n'·t/threads, so with 20,003 rows and 3 threads most chunks start and end off the
// 4-row passes: each row's arithmetic must not depend on where it falls.
TEST(ReconstructionKernel, AnyThreadCountGivesIdenticalBuffers) {
  for (const Eigen::Index m : {37, 100}) {
    const KernelCase c = randomCase(20003, m, 5);
    const std::vector<float> rest = interleavedPositions(c.rest);
    for (const KernelLoop loop : kLoops) {
      SCOPED_TRACE("m = " + std::to_string(m) + ", " + loopName(loop));
      std::vector<float> one(rest.size()), two(rest.size()), three(rest.size());
      reconstructInterleaved(c.K, rest, c.Z, one, 1, loop);
      reconstructInterleaved(c.K, rest, c.Z, two, 2, loop);
      reconstructInterleaved(c.K, rest, c.Z, three, 3, loop);
      EXPECT_EQ(one, two);
      EXPECT_EQ(one, three);
    }
  }
}

TEST(ReconstructionKernel, FastAndPortableLoopsAgreeToFloatRounding) {
  const KernelCase c = randomCase(4099, 100, 11);
  const std::vector<float> rest = interleavedPositions(c.rest);
  std::vector<float> fast(rest.size()), portable(rest.size());
  reconstructInterleaved(c.K, rest, c.Z, fast, 1, KernelLoop::Fastest);
  reconstructInterleaved(c.K, rest, c.Z, portable, 1, KernelLoop::Portable);
  const double scale = (c.K.cast<double>().cwiseAbs() * c.Z.cast<double>().cwiseAbs()).maxCoeff();
  double difference = 0.0;
  for (std::size_t i = 0; i < fast.size(); ++i)
    difference = std::max(difference, static_cast<double>(std::abs(fast[i] - portable[i])));
  EXPECT_LE(difference, 2e-6 * scale);
}

TEST(ReconstructionKernel, DescribesTheLoopItRuns) {
  EXPECT_STREQ(kernelLoopDescription(KernelLoop::Portable), "portable, 1 row per pass");
  EXPECT_NE(std::string(kernelLoopDescription(KernelLoop::Fastest)), "");
}

TEST(ReconstructionKernel, ZeroCoefficientsGiveTheRestPositions) {
  const KernelCase c = randomCase(100, 30, 9);
  const std::vector<float> rest = interleavedPositions(c.rest);
  std::vector<float> out(rest.size());
  for (const KernelLoop loop : kLoops) {
    reconstructInterleaved(c.K, rest, Eigen::MatrixXf::Zero(30, 3), out, 1, loop);
    EXPECT_EQ(out, rest) << loopName(loop);
  }
}

}  // namespace
}  // namespace sc::spectral
