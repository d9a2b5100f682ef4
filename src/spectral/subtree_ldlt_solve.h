#pragma once
// SubtreeLdltSolve: solves with a CHOLMOD simplicial LDLᵀ factor, its columns split over threads along the factor's
// elimination tree. Internal to src/spectral (ShiftInvertOperator::solveInFactorOrder(), block_lanczos.cpp's solves).

#include <Eigen/Core>

#include <cholmod.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace sc::spectral::detail {

/// Y = (L D Lᵀ)⁻¹ X for a simplicial LDLᵀ factor of CHOLMOD's (the system CHOLMOD_LDLt: X and Y in the factor's own
/// vertex order), every right-hand side of a group of four in one sweep over L, and L's columns split over threads.
///
/// Column j of L updates only rows that are ancestors of j in the elimination tree (parent(j) = the first row below
/// the diagonal), so disjoint subtrees are independent in both triangular sweeps. The tree is cut into subtrees,
/// dealt to the threads by weight (entries of L: each thread's share within 5% of even where the tree allows), and a
/// "top" of their common ancestors (2–5% of L on the dragons, 12% on the 100k dragon's seven components), which one
/// thread sweeps between the two parallel phases; a subtree's updates of top rows go to its thread's own buffer.
///
/// Why not cholmod_solve on each thread's share of the columns (the previous path): every thread then reads all of
/// L (150 MB at 437k vertices) twice per block, and CHOLMOD sweeps at most four right-hand sides per read of L,
/// two per thread here. Four columns, averages of 20 in one process (docs/benchmarks.md, thirteenth pass): at 437k
/// vertices 26–34 ms on two threads against 39–51 ms, 51–64 against 54–82 ms on one; at 1M 53–56 against 76–96 ms on
/// two. Sweeping the columns of a chain two at a time (as CHOLMOD does) measured no faster.
/// Not reentrant: solve() uses buffers of its own (#V × 4 doubles, a few top rows per thread); one per factor, whose
/// arrays it views (keep the factor alive and unchanged; build another after a new factorisation).
class SubtreeLdltSolve {
 public:
  /// The split for `threads` threads (≥ 1); nullopt when `factor` is not what the sweeps read: a simplicial, real,
  /// int-indexed LDLᵀ factor (not LLᵀ) whose columns' row indices are sorted. Cost: O(nnz(L)) to scan the columns,
  /// plus O(t·c log c) for t expansions of the tree's top among c candidate subtrees (0.02–0.2 s at 0.1–1M vertices).
  static std::optional<SubtreeLdltSolve> split(const cholmod_factor& factor, int threads);

  /// Y = (L D Lᵀ)⁻¹ X, X and Y #V × k in the factor's order (X must have #V rows; Y resized), in groups of four. Cost
  /// per group: one read of L per sweep, shared by the threads, plus a transposition of the group into and out of a
  /// row-major buffer.
  void solve(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const;

  int threads() const { return static_cast<int>(m_columns.size()); }
  /// Columns of L swept by one thread after the parallel phase (the subtrees' common ancestors).
  Eigen::Index topColumns() const { return static_cast<Eigen::Index>(m_top.size()); }
  /// Entries of L (D's included) in each thread's subtrees, then in the top: what each sweeps. Cost: O(#V).
  std::vector<std::int64_t> sweptEntries() const;

 private:
  /// A run of consecutive columns of L (in a postordered tree, one per subtree).
  struct ColumnRange {
    int first = 0;
    int last = 0;  ///< inclusive
  };

  SubtreeLdltSolve() = default;

  template <int Width>
  void solveGroup(const Eigen::MatrixXd& x, Eigen::Index firstColumn, Eigen::MatrixXd& y) const;

  const int* m_starts = nullptr;     ///< L->p: where each column begins (its first entry is D's)
  const int* m_counts = nullptr;     ///< L->nz: entries in each column, D's included
  const int* m_rows = nullptr;       ///< L->i: row indices, ascending within a column
  const double* m_values = nullptr;  ///< L->x
  int m_n = 0;
  std::vector<std::vector<ColumnRange>> m_columns;  ///< each thread's subtrees, ascending
  std::vector<int> m_top;                           ///< the top's columns, ascending
  std::vector<ColumnRange> m_topRanges;             ///< the same, as runs
  std::vector<int> m_topSlot;          ///< for a top row: its row in the threads' buffers; else −1 (#V entries)
  std::vector<int> m_topFrom;          ///< for a subtree column: where its entries in top rows begin (#V entries)
  mutable Eigen::VectorXd m_rowMajor;  ///< #V × 4, the group being solved, row-major (huge pages advised)
  mutable std::vector<std::vector<double>> m_topUpdates;  ///< per thread: top rows × 4
};

}  // namespace sc::spectral::detail
