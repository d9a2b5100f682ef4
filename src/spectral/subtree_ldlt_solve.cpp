#include "spectral/subtree_ldlt_solve.h"

#include "spectral/elimination_tree.h"
#include "spectral/huge_pages.h"
#include "spectral/parallel_ranges.h"

#include <algorithm>
#include <barrier>
#include <cassert>
#include <cstdint>
#include <utility>

namespace sc::spectral::detail {
namespace {

/// Whether the sweeps can read `factor` as they do: simplicial real LDLᵀ with int indices, D first in each column
/// and the rows below it ascending. Cost: one read of L's row indices.
bool sweepable(const cholmod_factor& factor) {
  if (factor.is_super != 0 || factor.is_ll != 0 || factor.xtype != CHOLMOD_REAL || factor.itype != CHOLMOD_INT ||
      factor.dtype != CHOLMOD_DOUBLE || factor.p == nullptr || factor.i == nullptr || factor.nz == nullptr ||
      factor.x == nullptr || factor.n == 0 || factor.n > static_cast<std::size_t>(INT32_MAX))
    return false;
  const auto* starts = static_cast<const int*>(factor.p);
  const auto* counts = static_cast<const int*>(factor.nz);
  const auto* rows = static_cast<const int*>(factor.i);
  const auto n = static_cast<int>(factor.n);
  for (int j = 0; j < n; ++j) {
    if (counts[j] < 1 || rows[starts[j]] != j) return false;
    for (int p = starts[j] + 1; p < starts[j] + counts[j]; ++p)
      if (rows[p] <= rows[p - 1] || rows[p] >= n) return false;
  }
  return true;
}

/// The elimination tree of a sweepable factor (parent(j) = the first row below the diagonal), weighted by the
/// entries of each column, which is what both sweeps read.
EliminationTree sweepTree(const int* starts, const int* counts, const int* rows, int n) {
  std::vector<int> parent(static_cast<std::size_t>(n), -1);
  std::vector<std::int64_t> entries(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    entries[static_cast<std::size_t>(j)] = counts[j];
    if (counts[j] >= 2) parent[static_cast<std::size_t>(j)] = rows[starts[j] + 1];
  }
  return {std::move(parent), std::move(entries)};
}

}  // namespace

std::optional<SubtreeLdltSolve> SubtreeLdltSolve::split(const cholmod_factor& factor, int threads) {
  if (!sweepable(factor)) return std::nullopt;
  threads = std::max(1, threads);
  SubtreeLdltSolve solver;
  solver.m_starts = static_cast<const int*>(factor.p);
  solver.m_counts = static_cast<const int*>(factor.nz);
  solver.m_rows = static_cast<const int*>(factor.i);
  solver.m_values = static_cast<const double*>(factor.x);
  const int n = solver.m_n = static_cast<int>(factor.n);
  const auto size = static_cast<std::size_t>(n);
  const std::vector<int> owner = subtreeOwners(sweepTree(solver.m_starts, solver.m_counts, solver.m_rows, n), threads);
  solver.m_columns.assign(static_cast<std::size_t>(threads), {});
  solver.m_topSlot.assign(size, -1);
  solver.m_topFrom.resize(size);
  for (int j = 0; j < n; ++j) {
    const int end = solver.m_starts[j] + solver.m_counts[j];
    const int mine = owner[static_cast<std::size_t>(j)];
    auto& ranges = mine < 0 ? solver.m_topRanges : solver.m_columns[static_cast<std::size_t>(mine)];
    if (!ranges.empty() && ranges.back().last == j - 1)
      ranges.back().last = j;
    else
      ranges.push_back({j, j});
    if (mine < 0) {
      solver.m_topSlot[static_cast<std::size_t>(j)] = static_cast<int>(solver.m_top.size());
      solver.m_top.push_back(j);
      solver.m_topFrom[static_cast<std::size_t>(j)] = end;  // the top's own sweep writes every row directly
      continue;
    }
    // a column's rows are its ancestors, ascending: those in its subtree, then those in the top
    int from = end;
    while (from - 1 > solver.m_starts[j] && owner[static_cast<std::size_t>(solver.m_rows[from - 1])] < 0) --from;
    solver.m_topFrom[static_cast<std::size_t>(j)] = from;
  }
  solver.m_topUpdates.assign(static_cast<std::size_t>(threads), std::vector<double>(4 * solver.m_top.size()));
  solver.m_rowMajor.resize(4 * static_cast<Eigen::Index>(n));
  adviseHugePages(solver.m_rowMajor.data(), static_cast<std::size_t>(solver.m_rowMajor.size()) * sizeof(double));
  return solver;
}

std::vector<std::int64_t> SubtreeLdltSolve::sweptEntries() const {
  std::vector<std::int64_t> entries;
  for (const auto& ranges : m_columns) {
    std::int64_t sum = 0;
    for (const ColumnRange& range : ranges)
      for (int j = range.first; j <= range.last; ++j) sum += m_counts[j];
    entries.push_back(sum);
  }
  std::int64_t top = 0;
  for (const int j : m_top) top += m_counts[j];
  entries.push_back(top);
  return entries;
}

void SubtreeLdltSolve::solve(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const {
  assert(x.rows() == m_n && "X must have the factor's #V rows");
  y.resize(x.rows(), x.cols());
  for (Eigen::Index first = 0; first < x.cols(); first += 4) {
    switch (std::min<Eigen::Index>(4, x.cols() - first)) {
      case 1:
        solveGroup<1>(x, first, y);
        break;
      case 2:
        solveGroup<2>(x, first, y);
        break;
      case 3:
        solveGroup<3>(x, first, y);
        break;
      default:
        solveGroup<4>(x, first, y);
        break;
    }
  }
}

template <int Width>
void SubtreeLdltSolve::solveGroup(const Eigen::MatrixXd& x, Eigen::Index firstColumn, Eigen::MatrixXd& y) const {
  double* z = m_rowMajor.data();
  const auto row = [z](int i) { return z + static_cast<std::ptrdiff_t>(Width) * i; };
  const auto load = [&](int j) {
    for (int c = 0; c < Width; ++c) row(j)[c] = x(j, firstColumn + c);
  };
  const auto store = [&](int j) {
    for (int c = 0; c < Width; ++c) y(j, firstColumn + c) = row(j)[c];
  };
  // L z = z, then z /= D, column by column: the entries before `from` update z, the rest `topUpdates`' slots
  const auto forward = [&](int j, double* topUpdates) {
    double a[Width];
    for (int c = 0; c < Width; ++c) a[c] = row(j)[c];
    const int start = m_starts[j];
    const int from = m_topFrom[static_cast<std::size_t>(j)];
    for (int p = start + 1; p < from; ++p) {
      double* target = row(m_rows[p]);
      for (int c = 0; c < Width; ++c) target[c] -= m_values[p] * a[c];
    }
    for (int p = from; p < start + m_counts[j]; ++p) {
      double* target = topUpdates + static_cast<std::ptrdiff_t>(Width) * m_topSlot[static_cast<std::size_t>(m_rows[p])];
      for (int c = 0; c < Width; ++c) target[c] -= m_values[p] * a[c];
    }
    const double pivot = m_values[start];
    for (int c = 0; c < Width; ++c) row(j)[c] = a[c] / pivot;
  };
  // Lᵀ z = z, column by column: z_j −= Σ L_ij z_i over its ancestors i, all final by then
  const auto backward = [&](int j) {
    double a[Width];
    for (int c = 0; c < Width; ++c) a[c] = row(j)[c];
    const int start = m_starts[j];
    for (int p = start + 1; p < start + m_counts[j]; ++p) {
      const double* source = row(m_rows[p]);
      for (int c = 0; c < Width; ++c) a[c] -= m_values[p] * source[c];
    }
    for (int c = 0; c < Width; ++c) row(j)[c] = a[c];
  };
  const auto sweepForward = [&](const std::vector<ColumnRange>& ranges, double* topUpdates) {
    for (const ColumnRange& range : ranges)
      for (int j = range.first; j <= range.last; ++j) forward(j, topUpdates);
  };
  const auto sweepBackward = [&](const std::vector<ColumnRange>& ranges) {
    for (auto range = ranges.rbegin(); range != ranges.rend(); ++range)
      for (int j = range->last; j >= range->first; --j) {
        backward(j);
        store(j);
      }
  };
  const auto sweepTop = [&]() noexcept {
    for (std::size_t slot = 0; slot < m_top.size(); ++slot) {
      const int j = m_top[slot];
      load(j);
      for (const auto& updates : m_topUpdates)
        for (int c = 0; c < Width; ++c) row(j)[c] += updates[Width * slot + static_cast<std::size_t>(c)];
    }
    sweepForward(m_topRanges, nullptr);
    sweepBackward(m_topRanges);
  };
  const int threads = this->threads();
  std::barrier topSwept(threads, sweepTop);
  parallelRanges(threads, threads, [&](std::ptrdiff_t thread, std::ptrdiff_t) {
    const auto& ranges = m_columns[static_cast<std::size_t>(thread)];
    std::vector<double>& topUpdates = m_topUpdates[static_cast<std::size_t>(thread)];
    std::fill(topUpdates.begin(), topUpdates.begin() + Width * static_cast<std::ptrdiff_t>(m_top.size()), 0.0);
    for (const ColumnRange& range : ranges)
      for (int j = range.first; j <= range.last; ++j) load(j);
    sweepForward(ranges, topUpdates.data());
    topSwept.arrive_and_wait();
    sweepBackward(ranges);
  });
}

}  // namespace sc::spectral::detail
