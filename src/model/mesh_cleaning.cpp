#include "model/mesh_cleaning.h"

#include "spectral/mesh_components.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cassert>
#include <compare>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace sc::model {
namespace {

using Triangle = std::array<int, 3>;
using Edge = std::pair<int, int>;

/// Twice a triangle's area is ‖(b−a)×(c−a)‖. Computing it in double from exactly collinear corners leaves a
/// rounding residue of a few ε·ℓ² (ℓ the longest edge); anything below this multiple of ℓ² counts as zero.
/// Genuine slivers (height/ℓ ≥ ~1e-13) are kept.
constexpr double kZeroAreaTolerance = 64 * std::numeric_limits<double>::epsilon();

std::size_t at(Eigen::Index i) { return static_cast<std::size_t>(i); }

Triangle face(const Eigen::MatrixXi& F, Eigen::Index f) { return {F(f, 0), F(f, 1), F(f, 2)}; }

/// Lexicographic order of positions; −0 equals +0 and NaNs are ordered too (std::strong_order), so sorting is
/// well defined for any input.
std::weak_ordering comparePositions(const Eigen::MatrixXd& V, int a, int b) {
  for (int k = 0; k < 3; ++k) {
    // Adding +0 turns −0 into +0 and leaves every other value as it is.
    const auto order = std::strong_order(V(a, k) + 0.0, V(b, k) + 0.0);
    if (order != 0) return order;
  }
  return std::weak_ordering::equivalent;
}

/// === step 1: for every vertex, the lowest-index vertex at exactly the same position (itself if none).
/// Cost: O(#V log #V).
std::vector<int> coincidentRepresentatives(const Eigen::MatrixXd& V, int& merged) {
  std::vector<int> order(at(V.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&V](int a, int b) {
    const auto c = comparePositions(V, a, b);
    return c != 0 ? c < 0 : a < b;
  });
  std::vector<int> representative(order.size());
  merged = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const bool sameAsPrevious = i > 0 && comparePositions(V, order[i - 1], order[i]) == 0;
    representative[at(order[i])] = sameAsPrevious ? representative[at(order[i - 1])] : order[i];
    merged += sameAsPrevious ? 1 : 0;
  }
  return representative;
}

bool hasRepeatedIndex(const Triangle& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

bool hasZeroArea(const Eigen::MatrixXd& V, const Triangle& t) {
  const Eigen::Vector3d a = V.row(t[0]).transpose(), b = V.row(t[1]).transpose(), c = V.row(t[2]).transpose();
  const double longest2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  return (b - a).cross(c - a).norm() <= kZeroAreaTolerance * longest2;
}

/// === step 4: marks every face over the same vertex set as an earlier kept face. Cost: O(#F log #F).
int dropDuplicateFaces(const std::vector<Triangle>& faces, std::vector<char>& keep) {
  std::vector<std::pair<Triangle, int>> keyed;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!keep[f]) continue;
    Triangle key = faces[f];
    std::sort(key.begin(), key.end());
    keyed.emplace_back(key, static_cast<int>(f));
  }
  std::sort(keyed.begin(), keyed.end());  // equal keys end up adjacent, the earliest face first
  int dropped = 0;
  for (std::size_t i = 1; i < keyed.size(); ++i) {
    if (keyed[i].first == keyed[i - 1].first) {
      keep[at(keyed[i].second)] = 0;
      ++dropped;
    }
  }
  return dropped;
}

/// === steps 2–4: faces remapped to representatives, with `keep` cleared for every dropped face.
std::vector<Triangle> filterFaces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                  const std::vector<int>& representative, std::vector<char>& keep,
                                  MeshCleanReport& report) {
  std::vector<Triangle> faces(at(F.rows()));
  keep.assign(faces.size(), 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Triangle& t = faces[at(f)];
    t = face(F, f);
    for (int& v : t) v = representative[at(v)];
    if (hasRepeatedIndex(t)) {
      keep[at(f)] = 0;
      ++report.droppedRepeatedIndexFaces;
    } else if (hasZeroArea(V, t)) {
      keep[at(f)] = 0;
      ++report.droppedZeroAreaFaces;
    }
  }
  report.droppedDuplicateFaces = dropDuplicateFaces(faces, keep);
  return faces;
}

/// === step 5: keeps the referenced vertices (in their order) and the kept faces (in theirs), re-indexed.
void compact(Eigen::MatrixXd& V, Eigen::MatrixXi& F, const std::vector<Triangle>& faces, const std::vector<char>& keep,
             const std::vector<int>& representative, MeshCleanReport& report) {
  std::vector<int> newIndex(at(V.rows()), -1);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (keep[f]) {
      for (const int v : faces[f]) newIndex[at(v)] = 0;
    }
  }
  int vertexCount = 0;
  for (std::size_t v = 0; v < newIndex.size(); ++v) {
    if (newIndex[v] == 0) {
      newIndex[v] = vertexCount++;
    } else if (representative[v] == static_cast<int>(v)) {
      ++report.droppedUnreferencedVertices;  // merged vertices were counted in step 1
    }
  }
  Eigen::MatrixXd keptV(vertexCount, 3);
  for (std::size_t v = 0; v < newIndex.size(); ++v) {
    if (newIndex[v] >= 0) keptV.row(newIndex[v]) = V.row(static_cast<Eigen::Index>(v));
  }
  const auto faceCount = static_cast<Eigen::Index>(std::count(keep.begin(), keep.end(), char{1}));
  Eigen::MatrixXi keptF(faceCount, 3);
  Eigen::Index row = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!keep[f]) continue;
    for (int k = 0; k < 3; ++k) keptF(row, k) = newIndex[at(faces[f][at(k)])];
    ++row;
  }
  V = std::move(keptV);
  F = std::move(keptF);
}

/// === steps 6–7: edges with more than two faces, and boundary loops: connected groups of edges with one face.
/// A loop is a connected component of the boundary-edge graph, so two holes touching at a vertex count as one.
/// Cost: O(#F log #F).
void countEdgeDiagnostics(Eigen::Index vertexCount, const Eigen::MatrixXi& F, MeshCleanReport& report) {
  std::vector<Edge> edges;
  edges.reserve(at(3 * F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<Edge> boundary;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) boundary.push_back(edges[i]);
    if (j - i > 2) ++report.nonManifoldEdges;
    i = j;
  }
  // Each boundary edge (a, b) becomes the degenerate triangle (a, b, b), whose graph edges are just a–b.
  Eigen::MatrixXi boundaryGraph(static_cast<Eigen::Index>(boundary.size()), 3);
  for (std::size_t e = 0; e < boundary.size(); ++e) {
    boundaryGraph.row(static_cast<Eigen::Index>(e)) << boundary[e].first, boundary[e].second, boundary[e].second;
  }
  Eigen::VectorXi labels;
  const int groups = spectral::connectedComponents(vertexCount, boundaryGraph, labels);
  std::vector<char> isLoop(at(groups), 0);
  for (const Edge& e : boundary) isLoop[at(labels(e.first))] = 1;
  report.boundaryLoops = static_cast<int>(std::count(isLoop.begin(), isLoop.end(), char{1}));
}

}  // namespace

MeshCleanReport cleanMesh(Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  assert((V.rows() == 0 || V.cols() == 3) && "V must be #V by 3");
  assert((F.rows() == 0 || F.cols() == 3) && "F must be #F by 3");
  assert((F.size() == 0 || (F.minCoeff() >= 0 && F.maxCoeff() < V.rows())) && "every index in F must be in [0, #V)");
  MeshCleanReport report;
  const std::vector<int> representative = coincidentRepresentatives(V, report.mergedDuplicateVertices);
  std::vector<char> keep;
  const std::vector<Triangle> faces = filterFaces(V, F, representative, keep, report);
  compact(V, F, faces, keep, representative, report);
  countEdgeDiagnostics(V.rows(), F, report);
  // === step 8: components of the cleaned mesh (every vertex is referenced now)
  Eigen::VectorXi labels;
  report.components = spectral::connectedComponents(V.rows(), F, labels);
  return report;
}

}  // namespace sc::model
