#include "spectral/mesh_components.h"

#include <numeric>
#include <vector>

namespace sc::spectral {
namespace {

/// Disjoint-set forest with path halving and union by size.
class UnionFind {
 public:
  explicit UnionFind(Eigen::Index n) : m_parent(static_cast<std::size_t>(n)), m_size(static_cast<std::size_t>(n), 1) {
    std::iota(m_parent.begin(), m_parent.end(), 0);
  }
  int find(int x) {
    while (m_parent[static_cast<std::size_t>(x)] != x) {
      auto& p = m_parent[static_cast<std::size_t>(x)];
      p = m_parent[static_cast<std::size_t>(p)];
      x = p;
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (m_size[static_cast<std::size_t>(a)] < m_size[static_cast<std::size_t>(b)]) std::swap(a, b);
    m_parent[static_cast<std::size_t>(b)] = a;
    m_size[static_cast<std::size_t>(a)] += m_size[static_cast<std::size_t>(b)];
  }

 private:
  std::vector<int> m_parent;
  std::vector<int> m_size;
};

int labelSets(UnionFind& sets, Eigen::Index vertexCount, Eigen::VectorXi& labels) {
  labels.setConstant(vertexCount, -1);
  std::vector<int> labelOfRoot(static_cast<std::size_t>(vertexCount), -1);
  int count = 0;
  for (Eigen::Index v = 0; v < vertexCount; ++v) {
    auto& label = labelOfRoot[static_cast<std::size_t>(sets.find(static_cast<int>(v)))];
    if (label < 0) label = count++;
    labels(v) = label;
  }
  return count;
}

}  // namespace

int connectedComponents(Eigen::Index vertexCount, const Eigen::MatrixXi& F, Eigen::VectorXi& labels) {
  UnionFind sets(vertexCount);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    sets.unite(F(f, 0), F(f, 1));
    sets.unite(F(f, 1), F(f, 2));
  }
  return labelSets(sets, vertexCount, labels);
}

int connectedComponents(const Eigen::SparseMatrix<double>& pattern, Eigen::VectorXi& labels) {
  UnionFind sets(pattern.rows());
  for (Eigen::Index j = 0; j < pattern.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(pattern, j); it; ++it)
      sets.unite(static_cast<int>(it.row()), static_cast<int>(it.col()));
  return labelSets(sets, pattern.rows(), labels);
}

}  // namespace sc::spectral
