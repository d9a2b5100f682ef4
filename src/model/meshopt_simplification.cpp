#include "model/meshopt_simplification.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace sc::model::detail {
namespace {

/// No error bound: meshopt_simplify stops on the triangle target (or topology) only. Relative to the mesh extent,
/// squared inside meshoptimizer, so it must stay far below sqrt(FLT_MAX).
constexpr float kNoErrorLimit = 1e10f;
/// Runs on the whole input while the result lands below the vertex target (each aimed higher).
constexpr int kMaxRestarts = 3;
/// Refinements of a result above the vertex target.
constexpr int kMaxRefinements = 8;

/// A triangle list with its vertices compacted: meshoptimizer's per-call cost has an O(#vertices) part (position
/// hash, classification), so refining a small result over a large vertex array would cost as much as the first run.
struct Compact {
  std::vector<float> positions;
  TriangleIndices indices;       ///< into positions
  std::vector<unsigned> source;  ///< per compact vertex: its index in the caller's array
};

Compact compact(const std::vector<float>& positions, const TriangleIndices& indices) {
  Compact out;
  std::vector<unsigned> local(positions.size() / 3, ~0u);
  out.indices.reserve(indices.size());
  for (const unsigned v : indices) {
    if (local[v] == ~0u) {
      local[v] = static_cast<unsigned>(out.source.size());
      out.source.push_back(v);
      out.positions.insert(out.positions.end(), positions.begin() + 3 * std::ptrdiff_t(v),
                           positions.begin() + 3 * std::ptrdiff_t(v) + 3);
    }
    out.indices.push_back(local[v]);
  }
  return out;
}

/// A result and its referenced vertex count, in the caller's numbering.
struct Attempt {
  TriangleIndices indices;
  std::size_t vertices = 0;
  std::size_t triangles() const { return indices.size() / 3; }
};

Attempt simplifyCompact(const Compact& mesh, std::size_t targetTriangles) {
  const TriangleIndices local = simplifyToTriangles(mesh.positions, mesh.indices, targetTriangles);
  Attempt out;
  out.indices.reserve(local.size());
  for (const unsigned v : local) out.indices.push_back(mesh.source[v]);
  out.vertices = referencedVertexCount(local, mesh.source.size());
  return out;
}

std::size_t scaled(std::size_t count, double factor) {
  return static_cast<std::size_t>(std::max(1.0, std::round(static_cast<double>(count) * factor)));
}

}  // namespace

std::size_t referencedVertexCount(const TriangleIndices& indices, std::size_t vertexCount) {
  std::vector<char> used(vertexCount, 0);
  for (const unsigned v : indices) used[v] = 1;
  return static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
}

TriangleIndices simplifyToTriangles(const std::vector<float>& positions, const TriangleIndices& indices,
                                    std::size_t targetTriangles) {
  if (3 * targetTriangles >= indices.size()) return indices;
  TriangleIndices out(indices.size());
  const std::size_t count =
      meshopt_simplify(out.data(), indices.data(), indices.size(), positions.data(), positions.size() / 3,
                       3 * sizeof(float), 3 * targetTriangles, kNoErrorLimit, 0, nullptr);
  out.resize(count);
  return out;
}

TriangleIndices simplifyToVertices(const std::vector<float>& positions, const TriangleIndices& indices,
                                   std::size_t targetVertices) {
  const Compact input = compact(positions, indices);
  const std::size_t n = input.source.size();
  if (targetVertices >= n) return indices;
  const std::size_t tolerance = std::max<std::size_t>(1, targetVertices / 200);
  // === whole input: triangles in proportion; coarse levels keep relatively more boundary, so this lands above
  const std::size_t triangles = indices.size() / 3;
  double share = static_cast<double>(targetVertices) / static_cast<double>(n);
  Attempt best = simplifyCompact(input, scaled(triangles, share));
  for (int i = 0; i < kMaxRestarts && best.vertices + tolerance < targetVertices; ++i) {
    share = std::min(1.0, share * static_cast<double>(targetVertices) /
                              static_cast<double>(std::max<std::size_t>(best.vertices, 1)) * 1.02);
    best = simplifyCompact(input, scaled(triangles, share));
  }
  // === refine the result down: aim at what is left, halving the step after landing below
  double damping = 1.0;
  for (int i = 0; i < kMaxRefinements && best.vertices > targetVertices + tolerance; ++i) {
    const double ratio = static_cast<double>(targetVertices) / static_cast<double>(best.vertices);
    const Attempt next =
        simplifyCompact(compact(positions, best.indices), scaled(best.triangles(), 1.0 - damping * (1.0 - ratio)));
    if (next.vertices >= best.vertices) break;  // nothing more can collapse
    if (next.vertices + tolerance < targetVertices) {
      damping /= 2;
      continue;
    }
    best = next;
  }
  return best.indices;
}

}  // namespace sc::model::detail
