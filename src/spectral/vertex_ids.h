#pragma once
// Typed vertex ids for the two id spaces of a session (OpenMesh's handle habit): a FullVertexId indexes the host's
// full-resolution mesh (rows of H, what Constraints carry on the wire); a DisplayVertexId indexes the level a peer
// displays (rows of K and of X̂'). A client at a lower resolution maps one to the other through P
// (dominantFullVertices() in resolution_level.h); mixing them without that map is a compile error.

#include <cstdint>
#include <span>
#include <vector>

namespace sc::spectral {

/// A vertex id in one id space; Tag tells the spaces apart. Explicit construction, no arithmetic, ordered.
template <typename Tag>
struct VertexId {
  std::uint32_t value = 0;

  constexpr VertexId() = default;
  constexpr explicit VertexId(std::uint32_t id) : value(id) {}
  [[nodiscard]] constexpr std::size_t index() const { return value; }
  // ==, != and < written out rather than a defaulted <=>: <compare> first in a Q_OBJECT header's include chain
  // breaks moc ("Parse error at std").
  friend constexpr bool operator==(VertexId a, VertexId b) { return a.value == b.value; }
  friend constexpr bool operator!=(VertexId a, VertexId b) { return a.value != b.value; }
  friend constexpr bool operator<(VertexId a, VertexId b) { return a.value < b.value; }
};

struct FullVertexTag {};
struct DisplayVertexTag {};
using FullVertexId = VertexId<FullVertexTag>;        ///< row of the full-resolution mesh and of H
using DisplayVertexId = VertexId<DisplayVertexTag>;  ///< row of the displayed level (X̂', K)

using FullVertexIds = std::vector<FullVertexId>;
using DisplayVertexIds = std::vector<DisplayVertexId>;

/// Ids of one space from plain indices (e.g. a picking result or a decoded message), in order. Cost: O(k).
template <typename Id>
[[nodiscard]] std::vector<Id> vertexIds(std::span<const std::uint32_t> indices) {
  std::vector<Id> ids;
  ids.reserve(indices.size());
  for (const std::uint32_t index : indices) ids.emplace_back(index);
  return ids;
}

/// The plain indices of typed ids, in order (for a wire message or a GPU buffer). Cost: O(k).
template <typename Tag>
[[nodiscard]] std::vector<std::uint32_t> plainIndices(std::span<const VertexId<Tag>> ids) {
  std::vector<std::uint32_t> indices;
  indices.reserve(ids.size());
  for (const VertexId<Tag> id : ids) indices.push_back(id.value);
  return indices;
}

}  // namespace sc::spectral
