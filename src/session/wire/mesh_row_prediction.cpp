#include "session/wire/mesh_row_prediction.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>

namespace sc::session {
namespace {

/// Breadth-first visiting order over the edges of `faces` (3f' indices; indices ≥ n' are ignored), restarting at
/// the lowest unvisited vertex, and for each vertex its neighbours (CSR: offsets n'+1, targets). Cost: O(n' + f').
struct Traversal {
  std::vector<std::uint32_t> order;        // n' vertices
  std::vector<std::uint32_t> rank;         // position of each vertex in order
  std::vector<std::uint32_t> offsets;      // n' + 1
  std::vector<std::uint32_t> targets;      // ≤ 6f'
  std::vector<std::uint32_t> faceOffsets;  // n' + 1: the faces around each vertex (valid faces only)
  std::vector<std::uint32_t> faceIds;      // ≤ 3f'
  std::span<const std::uint32_t> faces;    // 3f' corners
};

Traversal traversal(std::uint32_t n, std::span<const std::uint32_t> faces) {
  Traversal t;
  t.offsets.assign(std::size_t{n} + 1, 0);
  const auto valid = [&](std::size_t face) {
    return faces[3 * face] < n && faces[3 * face + 1] < n && faces[3 * face + 2] < n;
  };
  const std::size_t faceCount = faces.size() / 3;
  for (std::size_t face = 0; face < faceCount; ++face)
    if (valid(face))
      for (int k = 0; k < 3; ++k) t.offsets[faces[3 * face + static_cast<std::size_t>(k)] + 1] += 2;
  for (std::size_t v = 0; v < n; ++v) t.offsets[v + 1] += t.offsets[v];
  t.targets.resize(t.offsets[n]);
  std::vector<std::uint32_t> fill(t.offsets.begin(), t.offsets.end() - 1);
  for (std::size_t face = 0; face < faceCount; ++face) {
    if (!valid(face)) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = faces[3 * face + static_cast<std::size_t>(k)];
      const std::uint32_t b = faces[3 * face + static_cast<std::size_t>((k + 1) % 3)];
      const std::uint32_t c = faces[3 * face + static_cast<std::size_t>((k + 2) % 3)];
      t.targets[fill[a]++] = b;
      t.targets[fill[a]++] = c;
    }
  }
  t.faces = faces;
  t.faceOffsets.assign(std::size_t{n} + 1, 0);
  for (std::size_t face = 0; face < faceCount; ++face)
    if (valid(face))
      for (int k = 0; k < 3; ++k) ++t.faceOffsets[faces[3 * face + static_cast<std::size_t>(k)] + 1];
  for (std::size_t v = 0; v < n; ++v) t.faceOffsets[v + 1] += t.faceOffsets[v];
  t.faceIds.resize(t.faceOffsets[n]);
  std::vector<std::uint32_t> at(t.faceOffsets.begin(), t.faceOffsets.end() - 1);
  for (std::size_t face = 0; face < faceCount; ++face)
    if (valid(face))
      for (int k = 0; k < 3; ++k)
        t.faceIds[at[faces[3 * face + static_cast<std::size_t>(k)]]++] = static_cast<std::uint32_t>(face);
  constexpr std::uint32_t kUnvisited = std::numeric_limits<std::uint32_t>::max();
  t.rank.assign(n, kUnvisited);
  t.order.reserve(n);
  for (std::uint32_t start = 0; start < n; ++start) {
    if (t.rank[start] != kUnvisited) continue;
    std::size_t head = t.order.size();
    t.rank[start] = static_cast<std::uint32_t>(t.order.size());
    t.order.push_back(start);
    for (; head < t.order.size(); ++head) {
      const std::uint32_t v = t.order[head];
      for (std::uint32_t e = t.offsets[v]; e < t.offsets[v + 1]; ++e) {
        const std::uint32_t u = t.targets[e];
        if (t.rank[u] != kUnvisited) continue;
        t.rank[u] = static_cast<std::uint32_t>(t.order.size());
        t.order.push_back(u);
      }
    }
  }
  return t;
}

/// How many faces around a vertex the parallelogram search looks at (bounds its cost on hostile faces).
constexpr std::uint32_t kMaxFacesSearched = 16;

/// A visited vertex c opposite v across the edge (a, b): the third corner of another face on (a, b), or nullopt.
std::optional<std::uint32_t> opposite(const Traversal& t, std::uint32_t v, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t end = std::min(t.faceOffsets[a + 1], t.faceOffsets[a] + kMaxFacesSearched);
  for (std::uint32_t e = t.faceOffsets[a]; e < end; ++e) {
    const std::uint32_t* f = t.faces.data() + 3 * std::size_t{t.faceIds[e]};
    const bool hasB = f[0] == b || f[1] == b || f[2] == b;
    if (!hasB || f[0] == v || f[1] == v || f[2] == v) continue;
    const std::uint32_t c = f[0] != a && f[0] != b ? f[0] : (f[1] != a && f[1] != b ? f[1] : f[2]);
    if (c != a && c != b && t.rank[c] < t.rank[v]) return c;
  }
  return std::nullopt;
}

/// Row v's prediction, m values: the mean of the parallelogram predictions Q_a + Q_b − Q_c over the faces (v, a, b)
/// with a and b visited and a visited c across (a, b) (second order along the mesh); without one, the rounded mean
/// of the rows of its neighbours visited before it; 0 when none is.
void predict(const Traversal& t, std::uint32_t v, std::span<const std::int16_t> Q, std::uint32_t m,
             std::vector<std::int64_t>& sum, std::vector<std::int16_t>& out) {
  std::fill(sum.begin(), sum.end(), 0);
  std::int64_t count = 0;
  const auto row = [&](std::uint32_t u) { return Q.data() + std::size_t{u} * m; };
  const std::uint32_t faceEnd = std::min(t.faceOffsets[v + 1], t.faceOffsets[v] + kMaxFacesSearched);
  for (std::uint32_t e = t.faceOffsets[v]; e < faceEnd; ++e) {
    const std::uint32_t* f = t.faces.data() + 3 * std::size_t{t.faceIds[e]};
    const std::uint32_t a = f[0] == v ? f[1] : f[0];
    const std::uint32_t b = f[2] == v ? f[1] : f[2];
    if (a == v || b == v || a == b || t.rank[a] >= t.rank[v] || t.rank[b] >= t.rank[v]) continue;
    const std::optional<std::uint32_t> c = opposite(t, v, a, b);
    if (!c) continue;
    const std::int16_t *qa = row(a), *qb = row(b), *qc = row(*c);
    for (std::uint32_t j = 0; j < m; ++j) sum[j] += std::int64_t{qa[j]} + qb[j] - qc[j];
    ++count;
  }
  if (count > 0) {
    for (std::uint32_t j = 0; j < m; ++j) {
      const std::int64_t twice = 2 * sum[j] + count;  // round half up, then clamp to int16
      const std::int64_t q = twice >= 0 ? twice / (2 * count) : -((-twice + 2 * count - 1) / (2 * count));
      out[j] = static_cast<std::int16_t>(std::clamp<std::int64_t>(q, -32768, 32767));
    }
    return;
  }
  std::fill(sum.begin(), sum.end(), 0);
  for (std::uint32_t e = t.offsets[v]; e < t.offsets[v + 1]; ++e) {
    const std::uint32_t u = t.targets[e];
    if (t.rank[u] >= t.rank[v]) continue;
    const std::int16_t* neighbour = row(u);
    for (std::uint32_t j = 0; j < m; ++j) sum[j] += neighbour[j];
    ++count;
  }
  for (std::uint32_t j = 0; j < m; ++j) {
    if (count == 0) {
      out[j] = 0;
      continue;
    }
    const std::int64_t twice = 2 * sum[j] + count;  // floor((2·sum + count) / (2·count)): round half up
    const std::int64_t q = twice >= 0 ? twice / (2 * count) : -((-twice + 2 * count - 1) / (2 * count));
    out[j] = static_cast<std::int16_t>(q);
  }
}

std::uint16_t zigzag(std::int16_t r) {
  return static_cast<std::uint16_t>((static_cast<std::uint16_t>(r) << 1) ^ static_cast<std::uint16_t>(r >> 15));
}
std::int16_t unzigzag(std::uint16_t z) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(z >> 1) ^ static_cast<std::uint16_t>(-(z & 1)));
}
std::int16_t wrapSub(std::int16_t a, std::int16_t b) {
  return static_cast<std::int16_t>(
      static_cast<std::uint16_t>(static_cast<std::uint16_t>(a) - static_cast<std::uint16_t>(b)));
}
std::int16_t wrapAdd(std::int16_t a, std::int16_t b) {
  return static_cast<std::int16_t>(
      static_cast<std::uint16_t>(static_cast<std::uint16_t>(a) + static_cast<std::uint16_t>(b)));
}

/// Visits the rows in traversal order: `step(v, k, prediction)` for the k-th visited vertex v, after its
/// prediction from the rows visited before it; the step must leave row v final before returning.
template <class Step>
void visitPredicted(const Traversal& t, std::span<const std::int16_t> rows, std::uint32_t m, Step&& step) {
  std::vector<std::int64_t> sum(m);
  std::vector<std::int16_t> prediction(m);
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(t.order.size()); ++k) {
    const std::uint32_t v = t.order[k];
    predict(t, v, rows, m, sum, prediction);
    step(v, k, prediction);
  }
}

}  // namespace

std::vector<std::uint8_t> kResidualPlanes(std::span<const std::uint32_t> faces, std::span<const std::int16_t> rows,
                                          std::uint32_t n, std::uint32_t m) {
  const std::size_t cells = std::size_t{n} * m;
  std::vector<std::uint8_t> planes(2 * cells);
  visitPredicted(traversal(n, faces), rows, m,
                 [&](std::uint32_t v, std::uint32_t k, const std::vector<std::int16_t>& prediction) {
                   for (std::uint32_t j = 0; j < m; ++j) {
                     const std::uint16_t z = zigzag(wrapSub(rows[std::size_t{v} * m + j], prediction[j]));
                     const std::size_t at = std::size_t{j} * n + k;
                     planes[at] = static_cast<std::uint8_t>(z & 0xff);
                     planes[cells + at] = static_cast<std::uint8_t>(z >> 8);
                   }
                 });
  return planes;
}

std::vector<std::int16_t> kFromResidualPlanes(std::span<const std::uint32_t> faces,
                                              std::span<const std::uint8_t> planes, std::uint32_t n, std::uint32_t m) {
  const std::size_t cells = std::size_t{n} * m;
  std::vector<std::int16_t> rows(cells);
  visitPredicted(traversal(n, faces), rows, m,
                 [&](std::uint32_t v, std::uint32_t k, const std::vector<std::int16_t>& prediction) {
                   for (std::uint32_t j = 0; j < m; ++j) {
                     const std::size_t at = std::size_t{j} * n + k;
                     const auto z = static_cast<std::uint16_t>(planes[at] | (planes[cells + at] << 8));
                     rows[std::size_t{v} * m + j] = wrapAdd(prediction[j], unzigzag(z));
                   }
                 });
  return rows;
}

}  // namespace sc::session
