#include "spectral/elimination_tree.h"

#include "spectral/huge_pages.h"

#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <utility>

namespace sc::spectral::detail {
namespace {

/// A thread's share may exceed an even split by this factor before the tree's top is cut further.
constexpr double kBalance = 1.05;

std::size_t at(int j) { return static_cast<std::size_t>(j); }

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

/// The columns moved to the top, in the order they were cut, and how many of them the best estimate keeps.
struct TopCut {
  std::vector<int> cut;
  std::size_t kept = 0;
};

TopCut cutTop(const EliminationTree& tree, int threads) {
  const auto n = static_cast<int>(tree.parent.size());
  std::priority_queue<std::pair<std::int64_t, int>> candidates;
  std::int64_t candidateWeight = 0;
  for (int j = 0; j < n; ++j)
    if (tree.parent[at(j)] < 0) {
      candidates.emplace(tree.weight[at(j)], j);
      candidateWeight += tree.weight[at(j)];
    }
  const auto all = [&candidates] {
    auto copy = candidates;
    std::vector<std::pair<std::int64_t, int>> list;
    list.reserve(copy.size());
    for (; !copy.empty(); copy.pop()) list.push_back(copy.top());
    return list;
  };
  TopCut top;
  std::vector<std::vector<int>> bins;
  std::int64_t topWeight = 0;
  std::int64_t best = std::numeric_limits<std::int64_t>::max();
  while (threads > 1 && !candidates.empty() && topWeight < best) {
    const auto [heaviest, root] = candidates.top();
    const std::int64_t even = (candidateWeight + threads - 1) / threads;
    if (std::max(heaviest, even) + topWeight < best) {
      const std::int64_t share = deal(all(), threads, bins);
      if (share + topWeight < best) {
        best = share + topWeight;
        top.kept = top.cut.size();
      }
      if (static_cast<double>(share) <= kBalance * static_cast<double>(even)) break;
    }
    const int from = tree.childStart[at(root)];
    const int to = tree.childStart[at(root) + 1];
    if (from == to) break;
    candidates.pop();
    top.cut.push_back(root);
    topWeight += tree.own[at(root)];
    candidateWeight -= heaviest;
    for (int c = from; c < to; ++c) {
      const int child = tree.children[at(c)];
      candidates.emplace(tree.weight[at(child)], child);
      candidateWeight += tree.weight[at(child)];
    }
  }
  return top;
}

}  // namespace

EliminationTree::EliminationTree(std::vector<int> parents, std::vector<std::int64_t> ownWeights)
    : parent(std::move(parents)),
      own(std::move(ownWeights)),
      weight(hugePageVector(own.size(), std::int64_t{0})),
      childStart(hugePageVector(parent.size() + 1, 0)),
      children(hugePageVector(parent.size(), 0)) {
  const auto n = static_cast<int>(parent.size());
  std::copy(own.begin(), own.end(), weight.begin());
  for (int j = 0; j < n; ++j)
    if (const int up = parent[at(j)]; up >= 0) {
      weight[at(up)] += weight[at(j)];  // a parent's index is larger: its weight is complete when it is reached
      ++childStart[at(up) + 1];
    }
  std::partial_sum(childStart.begin(), childStart.end(), childStart.begin());
  std::vector<int> next(childStart.begin(), childStart.end() - 1);
  for (int j = 0; j < n; ++j)
    if (const int up = parent[at(j)]; up >= 0) children[at(next[at(up)]++)] = j;
}

std::vector<int> subtreeOwners(const EliminationTree& tree, int threads) {
  const auto n = static_cast<int>(tree.parent.size());
  threads = std::max(1, threads);
  const TopCut top = cutTop(tree, threads);
  constexpr int kTop = -1;
  constexpr int kUnset = -2;
  std::vector<int> owner = hugePageVector(at(n), kUnset);
  for (std::size_t c = 0; c < top.kept; ++c) owner[at(top.cut[c])] = kTop;
  std::vector<std::pair<std::int64_t, int>> subtrees;  // the best cut's: roots and the top's children
  for (int j = 0; j < n; ++j) {
    const int up = tree.parent[at(j)];
    if (owner[at(j)] != kTop && (up < 0 || owner[at(up)] == kTop)) subtrees.emplace_back(tree.weight[at(j)], j);
  }
  std::vector<std::vector<int>> bins;
  deal(std::move(subtrees), threads, bins);
  for (std::size_t t = 0; t < bins.size(); ++t)
    for (const int root : bins[t]) owner[at(root)] = static_cast<int>(t);
  for (int j = n - 1; j >= 0; --j)  // a column's parent comes first, descending
    if (owner[at(j)] == kUnset) owner[at(j)] = owner[at(tree.parent[at(j)])];
  return owner;
}

}  // namespace sc::spectral::detail
