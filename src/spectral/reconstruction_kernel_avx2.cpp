#include "spectral/reconstruction_kernel_avx2.h"

#include "spectral/parallel_ranges.h"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SC_RECONSTRUCTION_AVX2 1
#include <immintrin.h>
#define SC_TARGET_AVX2 __attribute__((target("avx2,fma")))
#endif

namespace sc::spectral::detail {

#ifdef SC_RECONSTRUCTION_AVX2
namespace {

constexpr std::ptrdiff_t kChunkColumns = 8;      // floats per ymm register
constexpr std::ptrdiff_t kChunkFloats = 3 * 8;   // one chunk of Z: x, y, z lanes side by side
constexpr std::ptrdiff_t kBlockRows = 4;         // rows per pass: 12 accumulators, 3 registers of Z, 1 of K
constexpr std::ptrdiff_t kBlockOutputs = 3 * 4;  // floats written per pass
constexpr std::ptrdiff_t kPrefetchBlocks = 8;    // software prefetch distance in passes (6.4 kB of int16 K at m = 100)

/// Z laid out for the loop: chunk by chunk, 24 floats each (8 of x, 8 of y, 8 of z).
struct ChunkedCoefficients {
  std::ptrdiff_t columns = 0;     ///< entries per row the loop reads: m, or 8 when m < 8 (rows then padded copies)
  std::ptrdiff_t fullChunks = 0;  ///< columns / 8
  bool tail = false;              ///< columns % 8 ≠ 0: one more chunk, the row's last 8 entries
  std::vector<float> z;           ///< (fullChunks + tail)·24 floats
};

ChunkedCoefficients chunked(const Eigen::MatrixXf& Z) {
  ChunkedCoefficients out;
  const std::ptrdiff_t m = Z.rows();
  out.columns = std::max(m, kChunkColumns);
  out.fullChunks = out.columns / kChunkColumns;
  out.tail = out.columns % kChunkColumns != 0;
  out.z.assign(static_cast<std::size_t>((out.fullChunks + (out.tail ? 1 : 0)) * kChunkFloats), 0.0f);
  const auto at = [&](std::ptrdiff_t chunk, Eigen::Index c, std::ptrdiff_t lane) -> float& {
    return out.z[static_cast<std::size_t>(chunk * kChunkFloats + c * kChunkColumns + lane)];
  };
  for (std::ptrdiff_t chunk = 0; chunk < out.fullChunks; ++chunk)
    for (Eigen::Index c = 0; c < 3; ++c)
      for (std::ptrdiff_t lane = 0; lane < kChunkColumns; ++lane) {
        const std::ptrdiff_t j = chunk * kChunkColumns + lane;
        at(chunk, c, lane) = j < m ? Z(j, c) : 0.0f;
      }
  if (out.tail)  // lanes of the row's last 8 entries; those a full chunk already counted stay zero
    for (Eigen::Index c = 0; c < 3; ++c)
      for (std::ptrdiff_t lane = 0; lane < kChunkColumns; ++lane) {
        const std::ptrdiff_t j = out.columns - kChunkColumns + lane;
        if (j >= out.fullChunks * kChunkColumns) at(out.fullChunks, c, lane) = Z(j, c);
      }
  return out;
}

SC_TARGET_AVX2 inline __m256 load8(const float* p) { return _mm256_loadu_ps(p); }

SC_TARGET_AVX2 inline __m256 load8(const std::int16_t* p) {
  return _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
}

/// a[3r + c] += K(row r, 8 entries at k + r·stride) ⊙ Z chunk's coordinate c, r = 0..3.
template <class T>
SC_TARGET_AVX2 inline void accumulateChunk(const T* k, std::ptrdiff_t stride, const float* zc, __m256 (&a)[12]) {
  __m256 zx = _mm256_loadu_ps(zc);
  __m256 zy = _mm256_loadu_ps(zc + kChunkColumns);
  __m256 zz = _mm256_loadu_ps(zc + 2 * kChunkColumns);
  // Keep Z in registers: left alone, GCC 12 folds the 3 loads into all 12 FMAs (16 loads per chunk instead of 7),
  // measured 3–5% slower.
  asm("" : "+x"(zx), "+x"(zy), "+x"(zz));
  const __m256 v0 = load8(k);
  a[0] = _mm256_fmadd_ps(v0, zx, a[0]);
  a[1] = _mm256_fmadd_ps(v0, zy, a[1]);
  a[2] = _mm256_fmadd_ps(v0, zz, a[2]);
  const __m256 v1 = load8(k + stride);
  a[3] = _mm256_fmadd_ps(v1, zx, a[3]);
  a[4] = _mm256_fmadd_ps(v1, zy, a[4]);
  a[5] = _mm256_fmadd_ps(v1, zz, a[5]);
  const __m256 v2 = load8(k + 2 * stride);
  a[6] = _mm256_fmadd_ps(v2, zx, a[6]);
  a[7] = _mm256_fmadd_ps(v2, zy, a[7]);
  a[8] = _mm256_fmadd_ps(v2, zz, a[8]);
  const __m256 v3 = load8(k + 3 * stride);
  a[9] = _mm256_fmadd_ps(v3, zx, a[9]);
  a[10] = _mm256_fmadd_ps(v3, zy, a[10]);
  a[11] = _mm256_fmadd_ps(v3, zz, a[11]);
}

/// Rows k, k + stride, k + 2·stride, k + 3·stride (each `columns` entries, see ChunkedCoefficients):
/// out[0..12) = rest[0..12) + their products with Z, xyz per row. Each accumulator's 8 lanes are summed as
/// ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)), the same for every row.
template <class T>
SC_TARGET_AVX2 void blockOfFourRows(const T* k, std::ptrdiff_t stride, const ChunkedCoefficients& Z, const float* rest,
                                    float* out) {
  __m256 a[12];
  for (__m256& v : a) v = _mm256_setzero_ps();
  const float* zc = Z.z.data();
  // The 4 rows are contiguous when read in place: each chunk consumes 32·sizeof(T) bytes of them on average, so
  // prefetching as much, kPrefetchBlocks passes ahead, keeps K streaming (a prefetch never faults).
  constexpr std::uintptr_t kChunkBytes = kBlockRows * kChunkColumns * sizeof(T);
  std::uintptr_t ahead = reinterpret_cast<std::uintptr_t>(k) +
                         static_cast<std::uintptr_t>(kPrefetchBlocks * kBlockRows * stride) * sizeof(T);
  for (std::ptrdiff_t chunk = 0; chunk < Z.fullChunks; ++chunk, zc += kChunkFloats, ahead += kChunkBytes) {
    for (std::uintptr_t line = 0; line < kChunkBytes; line += 64)
      _mm_prefetch(reinterpret_cast<const char*>(ahead + line), _MM_HINT_T0);
    accumulateChunk(k + chunk * kChunkColumns, stride, zc, a);
  }
  if (Z.tail) accumulateChunk(k + Z.columns - kChunkColumns, stride, zc, a);
  // 8 accumulators → one register of their 8 sums, in order.
  const __m256 h01 = _mm256_hadd_ps(a[0], a[1]), h23 = _mm256_hadd_ps(a[2], a[3]);
  const __m256 h45 = _mm256_hadd_ps(a[4], a[5]), h67 = _mm256_hadd_ps(a[6], a[7]);
  const __m256 q0 = _mm256_hadd_ps(h01, h23), q1 = _mm256_hadd_ps(h45, h67);  // lanes 0..3 | 4..7 halves
  const __m256 low = _mm256_add_ps(_mm256_permute2f128_ps(q0, q1, 0x20), _mm256_permute2f128_ps(q0, q1, 0x31));
  // the last 4 accumulators → one 128-bit register of their 4 sums.
  const __m256 q2 = _mm256_hadd_ps(_mm256_hadd_ps(a[8], a[9]), _mm256_hadd_ps(a[10], a[11]));
  const __m128 high = _mm_add_ps(_mm256_castps256_ps128(q2), _mm256_extractf128_ps(q2, 1));
  _mm256_storeu_ps(out, _mm256_add_ps(_mm256_loadu_ps(rest), low));
  _mm_storeu_ps(out + 8, _mm_add_ps(_mm_loadu_ps(rest + 8), high));
}

/// Rows [begin, end) of the n by m row-major K.
template <class T>
SC_TARGET_AVX2 void reconstructRange(const T* K, std::ptrdiff_t m, const ChunkedCoefficients& Z, const float* rest,
                                     float* out, std::ptrdiff_t begin, std::ptrdiff_t end) {
  std::ptrdiff_t i = begin;
  if (m == Z.columns)  // rows read in place
    for (; i + kBlockRows <= end; i += kBlockRows) blockOfFourRows(K + i * m, m, Z, rest + 3 * i, out + 3 * i);
  if (i == end) return;
  std::vector<T> rows(static_cast<std::size_t>(kBlockRows * Z.columns));  // the rest: zero-padded copies
  float restCopy[kBlockOutputs], outCopy[kBlockOutputs];
  for (; i < end; i += kBlockRows) {
    const std::ptrdiff_t count = std::min(kBlockRows, end - i);
    std::fill(rows.begin(), rows.end(), T{0});
    std::fill(std::begin(restCopy), std::end(restCopy), 0.0f);
    for (std::ptrdiff_t r = 0; r < count; ++r) std::copy_n(K + (i + r) * m, m, rows.data() + r * Z.columns);
    std::copy_n(rest + 3 * i, 3 * count, restCopy);
    blockOfFourRows(rows.data(), Z.columns, Z, restCopy, outCopy);
    std::copy_n(outCopy, 3 * count, out + 3 * i);
  }
}

template <class T>
void reconstructAllRows(const T* K, Eigen::Index n, Eigen::Index m, const float* rest, const Eigen::MatrixXf& Z,
                        float* out, int threads) {
  assert(avx2KernelAvailable() && "the CPU must have AVX2 and FMA");
  assert(Z.rows() == m && Z.cols() == 3 && "Z must be m by 3");
  const ChunkedCoefficients chunks = chunked(Z);
  parallelRanges(n, threads, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    reconstructRange(K, m, chunks, rest, out, begin, end);
  });
}

}  // namespace

bool avx2KernelAvailable() {
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return available;
}

void reconstructAvx2(const float* K, Eigen::Index n, Eigen::Index m, const float* rest, const Eigen::MatrixXf& Z,
                     float* out, int threads) {
  reconstructAllRows(K, n, m, rest, Z, out, threads);
}

void reconstructAvx2(const std::int16_t* K, Eigen::Index n, Eigen::Index m, const float* rest, const Eigen::MatrixXf& Z,
                     float* out, int threads) {
  reconstructAllRows(K, n, m, rest, Z, out, threads);
}

#else  // not x86-64: never available, never called

bool avx2KernelAvailable() { return false; }

void reconstructAvx2(const float*, Eigen::Index, Eigen::Index, const float*, const Eigen::MatrixXf&, float*, int) {
  assert(false && "no AVX2 kernel on this architecture");
}

void reconstructAvx2(const std::int16_t*, Eigen::Index, Eigen::Index, const float*, const Eigen::MatrixXf&, float*,
                     int) {
  assert(false && "no AVX2 kernel on this architecture");
}

#endif

}  // namespace sc::spectral::detail
