#include "spectral/banded_products.h"

#include "spectral/parallel_ranges.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace sc::spectral::detail {
namespace {

/// Rows per band: W's band (b ≤ 8 columns) takes at most 32 KB.
constexpr Eigen::Index kBand = 512;
/// Rows per band of W −= Q·H: OpenBLAS's kernel for a tall band times a thin H streams Q faster in longer bands (W's
/// band, b ≤ 8 columns, then takes at most 256 KB, still within L2). At 437k rows and 300 columns of Q on the two
/// cores: 62–74 ms against 87–88 ms with 512 rows, while Qᵀ·W was slower in the longer bands (66–84 ms against
/// 47–57 ms), so it keeps kBand.
constexpr Eigen::Index kSubtractionBand = 4096;

/// Σ over bands [row, row + rows) of #V of body(row, rows, partial), where body adds its band's share to a
/// `resultRows` × `resultCols` partial sum: one partial per thread chunk, added in chunk order; bands of `bandRows`.
template <class Body>
Eigen::MatrixXd sumOverBands(Eigen::Index n, Eigen::Index resultRows, Eigen::Index resultCols, int threads,
                             const Body& body, Eigen::Index bandRows = kBand) {
  const int chunks = std::clamp<int>(threads, 1, static_cast<int>(std::max<Eigen::Index>(1, n / kBand)));
  std::vector<Eigen::MatrixXd> partial(static_cast<std::size_t>(chunks), Eigen::MatrixXd::Zero(resultRows, resultCols));
  parallelRanges(chunks, chunks, [&](std::ptrdiff_t first, std::ptrdiff_t last) {
    for (std::ptrdiff_t chunk = first; chunk < last; ++chunk) {
      const Eigen::Index begin = n * chunk / chunks;
      const Eigen::Index end = n * (chunk + 1) / chunks;
      for (Eigen::Index row = begin; row < end; row += bandRows)
        body(row, std::min(bandRows, end - row), partial[static_cast<std::size_t>(chunk)]);
    }
  });
  Eigen::MatrixXd total = std::move(partial.front());
  for (std::size_t chunk = 1; chunk < partial.size(); ++chunk) total += partial[chunk];
  return total;
}

}  // namespace

Eigen::MatrixXd massProjection(const Eigen::Ref<const Eigen::MatrixXd>& q, const Eigen::VectorXd& mass,
                               const Eigen::MatrixXd& w, int threads) {
  return sumOverBands(w.rows(), q.cols(), w.cols(), threads,
                      [&](Eigen::Index row, Eigen::Index rows, Eigen::MatrixXd& sum) {
                        const Eigen::MatrixXd weighted = mass.segment(row, rows).asDiagonal() * w.middleRows(row, rows);
                        sum.noalias() += q.middleRows(row, rows).transpose() * weighted;
                      });
}

Eigen::MatrixXd subtractWithGram(Eigen::MatrixXd& w, const Eigen::Ref<const Eigen::MatrixXd>& q,
                                 const Eigen::MatrixXd& h, const Eigen::VectorXd& mass, int threads) {
  return sumOverBands(
      w.rows(), w.cols(), w.cols(), threads,
      [&](Eigen::Index row, Eigen::Index rows, Eigen::MatrixXd& gram) {
        auto band = w.middleRows(row, rows);
        band.noalias() -= q.middleRows(row, rows) * h;
        gram.noalias() += band.transpose() * (mass.segment(row, rows).asDiagonal() * band);
      },
      kSubtractionBand);
}

SubtractedBlock subtractWithGramAndProjection(Eigen::MatrixXd& w, const Eigen::Ref<const Eigen::MatrixXd>& q,
                                              const Eigen::MatrixXd& h, const Eigen::VectorXd& mass, int threads) {
  const Eigen::Index b = w.cols();
  const Eigen::MatrixXd sums = sumOverBands(  // the Gram matrix above the projection
      w.rows(), b + q.cols(), b, threads,
      [&](Eigen::Index row, Eigen::Index rows, Eigen::MatrixXd& sum) {
        auto band = w.middleRows(row, rows);
        const auto qBand = q.middleRows(row, rows);
        band.noalias() -= qBand * h;
        const Eigen::MatrixXd weighted = mass.segment(row, rows).asDiagonal() * band;
        sum.topRows(b).noalias() += band.transpose() * weighted;
        sum.bottomRows(q.cols()).noalias() += qBand.transpose() * weighted;
      },
      kSubtractionBand);
  return {sums.topRows(b), sums.bottomRows(q.cols())};
}

Eigen::MatrixXd multiplyWithGram(Eigen::MatrixXd& w, const Eigen::MatrixXd& r, const Eigen::VectorXd& mass,
                                 int threads) {
  return sumOverBands(w.rows(), w.cols(), w.cols(), threads,
                      [&](Eigen::Index row, Eigen::Index rows, Eigen::MatrixXd& gram) {
                        auto band = w.middleRows(row, rows);
                        const Eigen::MatrixXd product = band * r;
                        band = product;
                        gram.noalias() += band.transpose() * (mass.segment(row, rows).asDiagonal() * band);
                      });
}

void multiplyInto(const Eigen::MatrixXd& w, const Eigen::MatrixXd& r, const Eigen::VectorXd& mass,
                  Eigen::Ref<Eigen::MatrixXd> out, Eigen::MatrixXd& weighted, int threads) {
  const Eigen::Index n = w.rows();
  const Eigen::Index bands = (n + kBand - 1) / kBand;
  parallelRanges(bands, threads, [&](std::ptrdiff_t first, std::ptrdiff_t last) {
    for (Eigen::Index row = first * kBand; row < std::min(n, last * kBand); row += kBand) {
      const Eigen::Index rows = std::min(kBand, n - row);
      auto band = out.middleRows(row, rows);
      band.noalias() = w.middleRows(row, rows) * r;
      weighted.middleRows(row, rows).noalias() = mass.segment(row, rows).asDiagonal() * band;
    }
  });
}

Eigen::MatrixXd massGram(const Eigen::MatrixXd& w, const Eigen::VectorXd& mass, int threads) {
  return sumOverBands(w.rows(), w.cols(), w.cols(), threads,
                      [&](Eigen::Index row, Eigen::Index rows, Eigen::MatrixXd& gram) {
                        const auto band = w.middleRows(row, rows);
                        gram.noalias() += band.transpose() * (mass.segment(row, rows).asDiagonal() * band);
                      });
}

}  // namespace sc::spectral::detail
