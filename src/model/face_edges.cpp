#include "model/face_edges.h"

#include <algorithm>
#include <cstddef>

namespace sc::model::detail {

OutgoingEdges outgoingEdges(Eigen::Index vertexCount, const Eigen::MatrixXi& F) {
  OutgoingEdges edges;
  edges.offsets.assign(static_cast<std::size_t>(vertexCount) + 1, 0);
  for (Eigen::Index i = 0; i < F.size(); ++i) ++edges.offsets[static_cast<std::size_t>(F.data()[i]) + 1];
  for (std::size_t v = 1; v < edges.offsets.size(); ++v) edges.offsets[v] += edges.offsets[v - 1];
  edges.targets.resize(static_cast<std::size_t>(F.size()));
  edges.faces.resize(static_cast<std::size_t>(F.size()));
  std::vector<int> next(edges.offsets.begin(), edges.offsets.end() - 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto slot = static_cast<std::size_t>(next[static_cast<std::size_t>(F(f, k))]++);
      edges.targets[slot] = F(f, (k + 1) % 3);
      edges.faces[slot] = static_cast<int>(f);
    }
  return edges;
}

std::vector<char> refusedFaces(const Eigen::MatrixXi& F, const OutgoingEdges& edges) {
  std::vector<char> refused(static_cast<std::size_t>(F.rows()), 0);
  // Is a→b an edge of an accepted face before f? (a's edges are in face order: stop at f.)
  const auto usedBefore = [&](int a, int b, Eigen::Index f) {
    for (auto i = static_cast<std::size_t>(edges.offsets[static_cast<std::size_t>(a)]);; ++i) {
      const int face = edges.faces[i];
      if (face >= f) return false;
      if (edges.targets[i] == b && !refused[static_cast<std::size_t>(face)]) return true;
    }
  };
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    refused[static_cast<std::size_t>(f)] =
        a == b || b == c || c == a || usedBefore(a, b, f) || usedBefore(b, c, f) || usedBefore(c, a, f);
  }
  return refused;
}

std::vector<std::array<int, 3>> movedToKept(const std::vector<std::array<int, 3>>& faces, const std::vector<char>& kept,
                                            const OutgoingEdges& edges, const std::vector<char>& refused) {
  std::vector<std::array<int, 3>> moved = faces;
  std::vector<int> stamp(kept.size(), -1);  // the search that last visited each vertex
  std::vector<int> level, next;
  int search = 0;
  for (std::array<int, 3>& face : moved) {
    for (int& corner : face) {
      if (kept[static_cast<std::size_t>(corner)]) continue;
      // === breadth-first, one hop at a time, until a hop reaches kept vertices
      const int mark = search++;
      level.assign(1, corner);
      stamp[static_cast<std::size_t>(corner)] = mark;
      int chosen = -1;
      while (!level.empty() && chosen < 0) {
        next.clear();
        for (const int v : level) {
          const auto end = static_cast<std::size_t>(edges.offsets[static_cast<std::size_t>(v) + 1]);
          for (auto i = static_cast<std::size_t>(edges.offsets[static_cast<std::size_t>(v)]); i < end; ++i) {
            const int w = edges.targets[i];
            if (refused[static_cast<std::size_t>(edges.faces[i])] || stamp[static_cast<std::size_t>(w)] == mark)
              continue;
            stamp[static_cast<std::size_t>(w)] = mark;
            next.push_back(w);
          }
        }
        // the first kept vertex of this hop that the face does not already use, else the first kept one
        for (const int w : next) {
          if (!kept[static_cast<std::size_t>(w)]) continue;
          if (std::find(face.begin(), face.end(), w) == face.end()) {  // earlier corners as moved, later as they are
            chosen = w;
            break;
          }
          if (chosen < 0) chosen = w;
        }
        level.swap(next);
      }
      if (chosen >= 0) corner = chosen;
    }
  }
  return moved;
}

}  // namespace sc::model::detail
