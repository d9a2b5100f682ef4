#include "spectral/subtree_ldlt_solve.h"

#include "spectral/huge_pages.h"
#include "spectral/parallel_ranges.h"

#include <algorithm>
#include <barrier>
#include <cassert>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <utility>

namespace sc::spectral::detail {
namespace {

/// A thread's share may exceed an even split by this factor before the tree's top is cut further.
constexpr double kBalance = 1.05;

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

/// Subtrees (by root) dealt to `threads` bins, largest first onto the lightest bin (LPT); the heaviest bin's weight.
std::int64_t deal(std::vector<std::pair<std::int64_t, int>> candidates, int threads,
                  std::vector<std::vector<int>>& bins) {
  std::sort(candidates.begin(), candidates.end(), std::greater<>());
  std::vector<std::int64_t> load(static_cast<std::size_t>(threads), 0);
  bins.assign(static_cast<std::size_t>(threads), {});
  for (const auto& [weight, root] : candidates) {
    const auto lightest = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[lightest] += weight;
    bins[lightest].push_back(root);
  }
  return *std::max_element(load.begin(), load.end());
}

/// The elimination tree of a sweepable factor: parent(j) = the first row below the diagonal (−1 at a root), each
/// subtree's weight (the entries of L in its columns) and each column's children (children[childStart[j] ...
/// childStart[j + 1]]).
struct EliminationTree {
  std::vector<int> parent;
  std::vector<std::int64_t> weight;
  std::vector<int> childStart;
  std::vector<int> children;

  EliminationTree(const int* starts, const int* counts, const int* rows, int n)
      : parent(static_cast<std::size_t>(n), -1),
        weight(static_cast<std::size_t>(n)),
        childStart(static_cast<std::size_t>(n) + 1, 0),
        children(static_cast<std::size_t>(n)) {
    for (int j = 0; j < n; ++j) {
      weight[static_cast<std::size_t>(j)] += counts[j];
      if (counts[j] < 2) continue;
      const int up = rows[starts[j] + 1];  // a parent's index is larger: its weight is complete when it is reached
      parent[static_cast<std::size_t>(j)] = up;
      weight[static_cast<std::size_t>(up)] += weight[static_cast<std::size_t>(j)];
      ++childStart[static_cast<std::size_t>(up) + 1];
    }
    std::partial_sum(childStart.begin(), childStart.end(), childStart.begin());
    std::vector<int> next(childStart.begin(), childStart.end() - 1);
    for (int j = 0; j < n; ++j)
      if (const int up = parent[static_cast<std::size_t>(j)]; up >= 0)
        children[static_cast<std::size_t>(next[static_cast<std::size_t>(up)]++)] = j;
  }
};

/// Each column's owner: the thread (0 … threads − 1) that sweeps its subtree, or −1 for the top.
/// The top is cut from the roots down: the heaviest candidate subtree moves to the top and its children become
/// candidates, for as long as that can still shorten the estimated sweep, the heaviest thread's share of the
/// subtrees (dealt by deal()) plus the top (which one thread sweeps); the cut with the shortest estimate is kept.
/// Ends early once the shares are within kBalance of even, and at a leaf (which cannot be cut).
std::vector<int> owners(const EliminationTree& tree, const int* counts, int threads) {
  const auto n = static_cast<int>(tree.parent.size());
  const auto at = [](int j) { return static_cast<std::size_t>(j); };
  std::priority_queue<std::pair<std::int64_t, int>> candidates;
  std::int64_t candidateWeight = 0;
  for (int j = 0; j < n; ++j)
    if (tree.parent[at(j)] < 0) {
      candidates.emplace(tree.weight[at(j)], j);
      candidateWeight += tree.weight[at(j)];
    }
  std::vector<std::vector<int>> bins;
  const auto all = [&candidates] {
    auto copy = candidates;
    std::vector<std::pair<std::int64_t, int>> list;
    list.reserve(copy.size());
    for (; !copy.empty(); copy.pop()) list.push_back(copy.top());
    return list;
  };
  std::vector<int> cut;  // the columns moved to the top, in order
  std::int64_t topWeight = 0;
  std::int64_t best = std::numeric_limits<std::int64_t>::max();
  std::size_t bestCut = 0;
  while (threads > 1 && topWeight < best) {
    const auto [heaviest, root] = candidates.top();
    const std::int64_t even = (candidateWeight + threads - 1) / threads;
    if (std::max(heaviest, even) + topWeight < best) {
      const std::int64_t share = deal(all(), threads, bins);
      if (share + topWeight < best) {
        best = share + topWeight;
        bestCut = cut.size();
      }
      if (static_cast<double>(share) <= kBalance * static_cast<double>(even)) break;
    }
    const int from = tree.childStart[at(root)];
    const int to = tree.childStart[at(root) + 1];
    if (from == to) break;
    candidates.pop();
    cut.push_back(root);
    topWeight += counts[root];
    candidateWeight -= heaviest;
    for (int c = from; c < to; ++c) {
      const int child = tree.children[at(c)];
      candidates.emplace(tree.weight[at(child)], child);
      candidateWeight += tree.weight[at(child)];
    }
  }
  constexpr int kTop = -1;
  constexpr int kUnset = -2;
  std::vector<int> owner(at(n), kUnset);
  for (std::size_t c = 0; c < bestCut; ++c) owner[at(cut[c])] = kTop;
  std::vector<std::pair<std::int64_t, int>> subtrees;  // the best cut's: roots and the top's children
  for (int j = 0; j < n; ++j) {
    const int up = tree.parent[at(j)];
    if (owner[at(j)] != kTop && (up < 0 || owner[at(up)] == kTop)) subtrees.emplace_back(tree.weight[at(j)], j);
  }
  deal(std::move(subtrees), threads, bins);
  for (std::size_t t = 0; t < bins.size(); ++t)
    for (const int root : bins[t]) owner[at(root)] = static_cast<int>(t);
  for (int j = n - 1; j >= 0; --j)  // a column's parent comes first, descending
    if (owner[at(j)] == kUnset) owner[at(j)] = owner[at(tree.parent[at(j)])];
  return owner;
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
  const std::vector<int> owner =
      owners(EliminationTree(solver.m_starts, solver.m_counts, solver.m_rows, n), solver.m_counts, threads);
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
