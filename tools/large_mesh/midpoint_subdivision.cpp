#include "tools/large_mesh/midpoint_subdivision.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace sc::tools {

SubdividedMesh subdivideMidpoints(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const Eigen::Index faces = F.rows();
  // Every directed corner edge (face f, edge e = corner e → corner e+1) keyed by its undirected vertex pair.
  struct EdgeUse {
    std::uint64_t key;
    std::int64_t slot;  // 3·f + e
  };
  std::vector<EdgeUse> uses(static_cast<std::size_t>(3 * faces));
  for (Eigen::Index f = 0; f < faces; ++f) {
    for (int e = 0; e < 3; ++e) {
      const auto a = static_cast<std::uint32_t>(F(f, e));
      const auto b = static_cast<std::uint32_t>(F(f, (e + 1) % 3));
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      uses[static_cast<std::size_t>(3 * f + e)] = {key, 3 * f + e};
    }
  }
  // Midpoint index of each slot: edges numbered in order of first appearance (stable sort, then the smallest slot
  // of each key decides the order).
  std::vector<EdgeUse> sorted = uses;
  std::stable_sort(sorted.begin(), sorted.end(), [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key; });
  std::vector<std::int64_t> firstSlotOfSlot(uses.size());
  std::vector<std::int64_t> firstSlots;
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    while (j < sorted.size() && sorted[j].key == sorted[i].key) ++j;
    const std::int64_t first = sorted[i].slot;  // stable: the smallest slot of the key
    firstSlots.push_back(first);
    for (std::size_t k = i; k < j; ++k) firstSlotOfSlot[static_cast<std::size_t>(sorted[k].slot)] = first;
    i = j;
  }
  std::sort(firstSlots.begin(), firstSlots.end());
  std::vector<std::int64_t> edgeOfFirstSlot(uses.size(), -1);
  for (std::size_t e = 0; e < firstSlots.size(); ++e)
    edgeOfFirstSlot[static_cast<std::size_t>(firstSlots[e])] = static_cast<std::int64_t>(e);

  const Eigen::Index n = V.rows();
  const auto edges = static_cast<Eigen::Index>(firstSlots.size());
  SubdividedMesh out;
  out.V.resize(n + edges, 3);
  out.V.topRows(n) = V;
  for (Eigen::Index e = 0; e < edges; ++e) {
    const std::int64_t slot = firstSlots[static_cast<std::size_t>(e)];
    const Eigen::Index f = slot / 3;
    const int c = static_cast<int>(slot % 3);
    out.V.row(n + e) = 0.5 * (V.row(F(f, c)) + V.row(F(f, (c + 1) % 3)));
  }
  out.F.resize(4 * faces, 3);
  for (Eigen::Index f = 0; f < faces; ++f) {
    int mid[3];
    for (int e = 0; e < 3; ++e) {
      const std::int64_t first = firstSlotOfSlot[static_cast<std::size_t>(3 * f + e)];
      mid[e] = static_cast<int>(n + edgeOfFirstSlot[static_cast<std::size_t>(first)]);
    }
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    const int ab = mid[0], bc = mid[1], ca = mid[2];
    out.F.row(4 * f + 0) << a, ab, ca;
    out.F.row(4 * f + 1) << ab, b, bc;
    out.F.row(4 * f + 2) << ca, bc, c;
    out.F.row(4 * f + 3) << ab, bc, ca;
  }
  return out;
}

}  // namespace sc::tools
