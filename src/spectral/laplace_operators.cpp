#include "spectral/laplace_operators.h"

#include "spectral/huge_pages.h"
#include "spectral/parallel_ranges.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

namespace sc::spectral {
namespace {

/// Edge lengths of a face, l[k] = length of the edge opposite corner k.
using FaceLengths = std::array<double, 3>;

FaceLengths faceLengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f) {
  FaceLengths l{};
  for (int k = 0; k < 3; ++k)
    l[static_cast<std::size_t>(k)] = (V.row(F(f, (k + 1) % 3)) - V.row(F(f, (k + 2) % 3))).norm();
  return l;
}

/// Smallest ε ≥ 0 such that every face satisfies l_i + l_j ≥ l_k + δ after adding ε to all lengths.
double mollificationEpsilon(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double delta) {
  double epsilon = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const FaceLengths l = faceLengths(V, F, f);
    for (std::size_t k = 0; k < 3; ++k) epsilon = std::max(epsilon, delta - l[(k + 1) % 3] - l[(k + 2) % 3] + l[k]);
  }
  return epsilon;
}

/// Triangle area from its side lengths (Kahan's numerically stable Heron formula).
double heronArea(FaceLengths l) {
  std::sort(l.begin(), l.end(), std::greater<>());
  const double a = l[0], b = l[1], c = l[2];
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return 0.25 * std::sqrt(std::max(p, 0.0));
}

/// S's pattern in compressed column form, values zero: an entry (i, j) and (j, i) for every face edge {i, j} and
/// (i, i) for every vertex a face uses, each once — the pattern setFromTriplets() makes from the faces' triplets.
/// Cost: O(#V + #F) time (each column's few rows sorted in place), 24·#F bytes of rows transient.
SparseMatrix stiffnessPattern(Eigen::Index n, const Eigen::MatrixXi& F) {
  // Neighbours by column, duplicates included (an interior edge comes from both its faces), then sorted, made
  // unique and copied with the diagonal in its place.
  std::vector<int> starts(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) starts[static_cast<std::size_t>(F(f, k)) + 1] += 2;
  for (std::size_t c = 0; c < static_cast<std::size_t>(n); ++c) starts[c + 1] += starts[c];
  std::vector<int> next(starts.begin(), starts.end() - 1);
  const auto neighbours = std::make_unique_for_overwrite<int[]>(static_cast<std::size_t>(starts.back()));
  detail::adviseHugePages(neighbours.get(), static_cast<std::size_t>(starts.back()) * sizeof(int));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int& at = next[static_cast<std::size_t>(F(f, k))];
      neighbours[static_cast<std::size_t>(at++)] = F(f, (k + 1) % 3);
      neighbours[static_cast<std::size_t>(at++)] = F(f, (k + 2) % 3);
    }

  // Each column sorted and made unique (in parallel: columns are independent), then counted and copied.
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<int> counts(static_cast<std::size_t>(n));
  detail::parallelRanges(n, threads, [&](std::ptrdiff_t first, std::ptrdiff_t last) {
    for (std::ptrdiff_t c = first; c < last; ++c) {
      int* begin = neighbours.get() + starts[static_cast<std::size_t>(c)];
      int* end = neighbours.get() + starts[static_cast<std::size_t>(c) + 1];
      std::sort(begin, end);
      const int unique = static_cast<int>(std::unique(begin, end) - begin);
      next[static_cast<std::size_t>(c)] = unique;
      const bool listsItself = std::binary_search(begin, begin + unique, static_cast<int>(c));  // a face {c, c, …}
      counts[static_cast<std::size_t>(c)] = unique + (unique > 0 && !listsItself ? 1 : 0);      // + the diagonal
    }
  });
  SparseMatrix S(n, n);
  int* outer = S.outerIndexPtr();
  outer[0] = 0;
  for (Eigen::Index c = 0; c < n; ++c) outer[c + 1] = outer[c] + counts[static_cast<std::size_t>(c)];
  S.resizeNonZeros(outer[n]);
  detail::adviseHugePages(S.innerIndexPtr(), static_cast<std::size_t>(outer[n]) * sizeof(int));
  detail::adviseHugePages(S.valuePtr(), static_cast<std::size_t>(outer[n]) * sizeof(double));
  detail::parallelRanges(n, threads, [&](std::ptrdiff_t first, std::ptrdiff_t last) {
    for (std::ptrdiff_t c = first; c < last; ++c) {
      if (outer[c + 1] == outer[c]) continue;  // no face uses c: an empty column
      const int* begin = neighbours.get() + starts[static_cast<std::size_t>(c)];
      const int* end = begin + next[static_cast<std::size_t>(c)];
      const int* split = std::lower_bound(begin, end, static_cast<int>(c));
      int* out = std::copy(begin, split, S.innerIndexPtr() + outer[c]);
      *out++ = static_cast<int>(c);
      std::copy(split + (split != end && *split == c ? 1 : 0), end, out);
      std::fill(S.valuePtr() + outer[c], S.valuePtr() + outer[c + 1], 0.0);
    }
  });
  return S;
}

/// S(row, column) += value on an entry of S's pattern. Cost: O(entries in the column), a few.
void addToEntry(SparseMatrix& S, int row, int column, double value) {
  const int* rows = S.innerIndexPtr();
  int at = S.outerIndexPtr()[column];
  while (rows[at] != row) ++at;
  S.valuePtr()[at] += value;
}

}  // namespace

LaplaceOperators laplaceOperators(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const LaplaceOptions& options) {
  assert(V.cols() == 3 && F.cols() == 3 && "V and F must have three columns");
  const Eigen::Index n = V.rows();

  // === step 1: the mollification that keeps every triangle non-degenerate (lengths are recomputed, not stored)
  double lengthSum = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (double l : faceLengths(V, F, f)) lengthSum += l;
  const double meanEdge = F.rows() > 0 ? lengthSum / (3.0 * static_cast<double>(F.rows())) : 0.0;
  LaplaceOperators ops;
  ops.mollifyEpsilon = mollificationEpsilon(V, F, options.mollifyMargin * meanEdge);

  // === step 2: per-face cotangent weights and lumped areas, summed into S's pattern and M
  SparseMatrix pattern = stiffnessPattern(n, F);
  ops.stiffness.swap(pattern);  // not an assignment: that would copy it (Eigen 3.4 has no sparse move)
  ops.mass.setZero(n);
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);  // summed apart, in the same order, then stored
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    FaceLengths l = faceLengths(V, F, f);
    for (double& x : l) x += ops.mollifyEpsilon;
    const double area = heronArea(l);
    for (int k = 0; k < 3; ++k) {
      const auto sk = static_cast<std::size_t>(k);
      const double a = l[sk], b = l[(sk + 1) % 3], c = l[(sk + 2) % 3];
      const double w = area > 0.0 ? 0.5 * (b * b + c * c - a * a) / (4.0 * area) : 0.0;
      const int i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      addToEntry(ops.stiffness, i, j, -w);
      addToEntry(ops.stiffness, j, i, -w);
      diagonal(i) += w;
      diagonal(j) += w;
      ops.mass(F(f, k)) += area / 3.0;
    }
    ops.totalArea += area;
  }
  for (Eigen::Index c = 0; c < n; ++c)
    if (ops.stiffness.outerIndexPtr()[c + 1] > ops.stiffness.outerIndexPtr()[c])
      addToEntry(ops.stiffness, static_cast<int>(c), static_cast<int>(c), diagonal(c));
  return ops;
}

}  // namespace sc::spectral
