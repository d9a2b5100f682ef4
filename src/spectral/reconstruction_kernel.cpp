#include "spectral/reconstruction_kernel.h"

#include "spectral/parallel_ranges.h"
#include "spectral/reconstruction_kernel_avx2.h"

#include <cassert>

namespace sc::spectral {
namespace {

/// Partial sums per coordinate of the portable loop: one 512-bit register of floats, or two 256-bit ones.
constexpr Eigen::Index kLanes = 16;

/// The portable loop, one row at a time: out[3i + c] = rest[3i + c] + Σ_k K(i, k)·Z(k, c) for rows [begin, end);
/// K float32 or int16 (converted to float per entry), vectorised lane-wise by the compiler for whatever the build
/// targets.
template <class T>
void reconstructRows(const T* K, Eigen::Index m, const float* z0, const float* z1, const float* z2, const float* rest,
                     float* out, std::ptrdiff_t begin, std::ptrdiff_t end) {
  for (std::ptrdiff_t i = begin; i < end; ++i) {
    const T* k = K + i * m;
    float a0[kLanes] = {}, a1[kLanes] = {}, a2[kLanes] = {};
    Eigen::Index j = 0;
    for (; j + kLanes <= m; j += kLanes)
      for (Eigen::Index l = 0; l < kLanes; ++l) {  // lane-wise: vectorises without reassociation
        const auto v = static_cast<float>(k[j + l]);
        a0[l] += v * z0[j + l];
        a1[l] += v * z1[j + l];
        a2[l] += v * z2[j + l];
      }
    for (Eigen::Index l = 0; j + l < m; ++l) {  // tail, m mod 16 terms
      const auto v = static_cast<float>(k[j + l]);
      a0[l] += v * z0[j + l];
      a1[l] += v * z1[j + l];
      a2[l] += v * z2[j + l];
    }
    for (Eigen::Index w = kLanes / 2; w >= 1; w /= 2)  // pairwise horizontal sums
      for (Eigen::Index l = 0; l < w; ++l) {
        a0[l] += a0[l + w];
        a1[l] += a1[l + w];
        a2[l] += a2[l + w];
      }
    out[3 * i + 0] = rest[3 * i + 0] + a0[0];
    out[3 * i + 1] = rest[3 * i + 1] + a1[0];
    out[3 * i + 2] = rest[3 * i + 2] + a2[0];
  }
}

template <class T>
void reconstructAll(const T* K, Eigen::Index n, Eigen::Index m, std::span<const float> rest, const Eigen::MatrixXf& Z,
                    std::span<float> out, int threads, KernelLoop loop) {
  assert(Z.rows() == m && Z.cols() == 3 && "Z must be m by 3");
  assert(rest.size() == static_cast<std::size_t>(3 * n) && out.size() == rest.size() && "buffers must be 3·n'");
  if (loop == KernelLoop::Fastest && detail::avx2KernelAvailable()) {
    detail::reconstructAvx2(K, n, m, rest.data(), Z, out.data(), threads);
    return;
  }
  detail::parallelRanges(n, threads, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    reconstructRows(K, m, Z.col(0).data(), Z.col(1).data(), Z.col(2).data(), rest.data(), out.data(), begin, end);
  });
}

}  // namespace

std::vector<float> interleavedPositions(const Eigen::MatrixXd& V) {
  std::vector<float> out(3 * static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (Eigen::Index c = 0; c < 3; ++c) out[static_cast<std::size_t>(3 * i + c)] = static_cast<float>(V(i, c));
  return out;
}

const char* kernelLoopDescription(KernelLoop loop) {
  if (loop == KernelLoop::Fastest && detail::avx2KernelAvailable()) return "AVX2+FMA, 4 rows per pass";
  return "portable, 1 row per pass";
}

void reconstructInterleaved(const RowMatrixXf& K, std::span<const float> rest, const Eigen::MatrixXf& Z,
                            std::span<float> out, int threads, KernelLoop loop) {
  reconstructAll(K.data(), K.rows(), K.cols(), rest, Z, out, threads, loop);
}

void reconstructInterleaved(const QuantizedBasis& K, std::span<const float> rest, const Eigen::MatrixXf& Z,
                            std::span<float> out, int threads, KernelLoop loop) {
  assert(Z.rows() == K.cols() && Z.cols() == 3 && "Z must be m by 3");
  const Eigen::MatrixXf scaledZ = K.scaled(Z);  // m by 3, once per frame
  reconstructAll(K.Q.data(), K.rows(), K.cols(), rest, scaledZ, out, threads, loop);
}

}  // namespace sc::spectral
