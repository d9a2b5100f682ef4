#pragma once
// EliminationTree and subtreeOwners(): a sparse LDLᵀ factor's elimination tree, cut into disjoint subtrees dealt to
// threads plus a "top" of their common ancestors. Internal to src/spectral (SubtreeLdltSolve's sweeps,
// UpLookingLdlt's rows).

#include <cstdint>
#include <vector>

namespace sc::spectral::detail {

/// The elimination tree of an n × n factor: parent(j) > j (−1 at a root), each column's own weight (the work it
/// costs: its entries for a solve, their square for a factorisation), each subtree's weight, and each column's
/// children (children[childStart[j] ... childStart[j + 1]]).
struct EliminationTree {
  std::vector<int> parent;
  std::vector<std::int64_t> own;
  std::vector<std::int64_t> weight;
  std::vector<int> childStart;
  std::vector<int> children;

  /// From each column's parent (greater than the column, or −1) and own weight (same length). Cost: O(n).
  EliminationTree(std::vector<int> parents, std::vector<std::int64_t> ownWeights);
};

/// Each column's owner: the thread (0 … threads − 1) whose subtrees hold it, or −1 for the top, which one thread
/// works through after the threads' subtrees (every column of a subtree has all its descendants in that subtree, so
/// threads never share one). The top is cut from the roots down: the heaviest candidate subtree moves to the top and
/// its children become candidates, for as long as that can still shorten the estimate "heaviest thread's share of the
/// subtrees (dealt largest first onto the lightest thread) + the top"; the cut with the shortest estimate is kept.
/// Ends early once the shares are within 5% of even, and at a leaf (which cannot be cut). threads ≤ 1: every column
/// is thread 0's. Cost: O(n) plus O(t·c log c) for t cuts among c candidate subtrees.
std::vector<int> subtreeOwners(const EliminationTree& tree, int threads);

}  // namespace sc::spectral::detail
