#include "spectral/up_looking_ldlt.h"

#include "spectral/elimination_tree.h"
#include "spectral/huge_pages.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <numeric>
#include <thread>
#include <vector>

namespace sc::spectral::detail {
namespace {

std::size_t at(int j) { return static_cast<std::size_t>(j); }

/// The upper triangle of P A Pᵀ by columns (row indices below or at the column), from A's lower triangle.
struct PermutedUpper {
  std::vector<int> starts;
  std::vector<int> rows;
  std::vector<double> values;

  PermutedUpper(const SparseMatrix& a, const int* order)
      : starts(hugePageVector(static_cast<std::size_t>(a.cols()) + 1, 0)) {
    const auto n = static_cast<int>(a.cols());
    std::vector<int> inverse = hugePageVector(at(n), 0);
    for (int i = 0; i < n; ++i) inverse[at(order[i])] = i;
    const auto forEach = [&](auto&& visit) {
      for (int c = 0; c < n; ++c)
        for (SparseMatrix::InnerIterator it(a, c); it; ++it)
          if (it.row() >= c) {
            const int i = inverse[at(static_cast<int>(it.row()))];
            const int k = inverse[at(c)];
            visit(std::min(i, k), std::max(i, k), it.value());
          }
    };
    forEach([&](int, int column, double) { ++starts[at(column) + 1]; });
    std::partial_sum(starts.begin(), starts.end(), starts.begin());
    rows = hugePageVector(at(starts.back()), 0);
    values = hugePageVector(at(starts.back()), 0.0);
    std::vector<int> next = hugePageVector(at(n), 0);  // where each column's next entry goes
    std::copy(starts.begin(), starts.end() - 1, next.begin());
    forEach([&](int row, int column, double value) {
      const auto slot = at(next[at(column)]++);
      rows[slot] = row;
      values[slot] = value;
    });
  }
};

/// parent(j) = the smallest k > j with L(k, j) ≠ 0 (Liu's algorithm, without path compression: the same paths the
/// numeric rows walk). Cost: O(nnz(L)).
std::vector<int> eliminationParents(const PermutedUpper& c, int n) {
  std::vector<int> parent = hugePageVector(at(n), -1);
  std::vector<int> flag = hugePageVector(at(n), 0);
  for (int k = 0; k < n; ++k) {
    flag[at(k)] = k;
    for (int p = c.starts[at(k)]; p < c.starts[at(k) + 1]; ++p)
      for (int i = c.rows[at(p)]; flag[at(i)] != k; i = parent[at(i)]) {
        if (parent[at(i)] == -1) parent[at(i)] = k;
        flag[at(i)] = k;
      }
  }
  return parent;
}

/// The factor's arrays and the state the rows share (each row touches only entries of its own subtree).
struct UpLooking {
  const PermutedUpper& c;
  const std::vector<int>& parent;
  const int* starts;
  int* counts;
  int* rows;
  double* values;
  int n;
  std::vector<double> y;  ///< the row being formed, scattered (zero outside it)
  std::vector<int> flag;  ///< flag[i] = k once i is in row k's pattern

  /// Rows `ks` (ascending, each one's descendants already done or among them). Returns the first whose pivot is zero
  /// or not finite, else n.
  int factorRows(const std::vector<int>& ks) {
    const auto pattern = std::make_unique_for_overwrite<int[]>(at(n));  // filled from the end: few pages touched
    for (const int k : ks) {
      int top = n;
      flag[at(k)] = k;
      counts[k] = 1;
      rows[starts[k]] = k;
      for (int p = c.starts[at(k)]; p < c.starts[at(k) + 1]; ++p) {
        int i = c.rows[at(p)];
        y[at(i)] += c.values[at(p)];
        int length = 0;
        for (; flag[at(i)] != k; i = parent[at(i)]) {
          pattern[at(length++)] = i;
          flag[at(i)] = k;
        }
        while (length > 0) pattern[at(--top)] = pattern[at(--length)];
      }
      double pivot = y[at(k)];
      y[at(k)] = 0.0;
      for (; top < n; ++top) {
        const int i = pattern[at(top)];
        const double yi = y[at(i)];
        y[at(i)] = 0.0;
        const int end = starts[i] + counts[i];
        for (int p = starts[i] + 1; p < end; ++p) y[at(rows[p])] -= values[p] * yi;
        const double l = yi / values[starts[i]];
        pivot -= l * yi;
        rows[end] = k;
        values[end] = l;
        ++counts[i];
      }
      values[starts[k]] = pivot;
      if (pivot == 0.0 || !std::isfinite(pivot)) return k;
    }
    return n;
  }
};

bool factorable(const SparseMatrix& a, const cholmod_factor& factor) {
  return a.isCompressed() && a.rows() == a.cols() && factor.n == static_cast<std::size_t>(a.cols()) && factor.n > 0 &&
         factor.n < static_cast<std::size_t>(INT32_MAX) && factor.is_super == 0 && factor.itype == CHOLMOD_INT &&
         factor.Perm != nullptr && factor.ColCount != nullptr &&
         (factor.xtype == CHOLMOD_PATTERN || (factor.xtype == CHOLMOD_REAL && factor.is_ll == 0));
}

}  // namespace

bool factorUpLooking(const SparseMatrix& a, cholmod_factor& factor, int threads, cholmod_common& common) {
  if (!factorable(a, factor)) return false;
  const auto n = static_cast<int>(factor.n);
  const auto* columnCounts = static_cast<const int*>(factor.ColCount);
  std::int64_t entries = 0;
  for (int j = 0; j < n; ++j) entries += columnCounts[j];
  if (entries >= INT32_MAX) return false;
  const PermutedUpper c(a, static_cast<const int*>(factor.Perm));
  const std::vector<int> parent = eliminationParents(c, n);
  // numeric, packed (no room between columns), monotonic; CHOLMOD allocates at least the column counts' sum
  if (!cholmod_change_factor(CHOLMOD_REAL, false, false, true, true, &factor, &common) ||
      factor.nzmax < static_cast<std::size_t>(entries))
    return false;
  auto* starts = static_cast<int*>(factor.p);
  int start = 0;
  for (int j = 0; j < n; ++j) {
    starts[j] = start;
    start += columnCounts[j];
  }
  starts[n] = start;
  UpLooking work{c,
                 parent,
                 starts,
                 static_cast<int*>(factor.nz),
                 static_cast<int*>(factor.i),
                 static_cast<double*>(factor.x),
                 n,
                 hugePageVector(at(n), 0.0),
                 hugePageVector(at(n), -1)};
  std::vector<std::int64_t> flops = hugePageVector(at(n), std::int64_t{0});
  for (int j = 0; j < n; ++j) flops[at(j)] = static_cast<std::int64_t>(columnCounts[j]) * columnCounts[j];
  const std::vector<int> owner = subtreeOwners(EliminationTree(parent, std::move(flops)), threads);
  const int shares = std::max(1, threads);
  const auto share = [&owner, shares](int k) { return owner[at(k)] < 0 ? at(shares) : at(owner[at(k)]); };
  std::vector<std::size_t> sizes(at(shares) + 1, 0);
  for (int k = 0; k < n; ++k) ++sizes[share(k)];
  std::vector<std::vector<int>> rowsOf(at(shares) + 1);  // each thread's, then the top's
  for (std::size_t s = 0; s < rowsOf.size(); ++s) rowsOf[s].reserve(sizes[s]);
  for (int k = 0; k < n; ++k) rowsOf[share(k)].push_back(k);
  std::vector<int> failed(at(shares) + 1, n);
  {
    std::vector<std::jthread> others;
    for (int t = 1; t < shares; ++t)
      others.emplace_back([&work, &rowsOf, &failed, t] { failed[at(t)] = work.factorRows(rowsOf[at(t)]); });
    failed[0] = work.factorRows(rowsOf[0]);
  }
  const int firstFailed = *std::min_element(failed.begin(), failed.end() - 1);
  failed[at(shares)] = firstFailed < n ? n : work.factorRows(rowsOf[at(shares)]);
  factor.minor = static_cast<std::size_t>(std::min(firstFailed, failed[at(shares)]));
  factor.is_ll = false;
  factor.is_monotonic = true;
  return true;
}

}  // namespace sc::spectral::detail
