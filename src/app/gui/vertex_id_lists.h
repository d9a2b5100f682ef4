#pragma once
// Typed vertex ids (spectral/vertex_ids.h) from and to the plain ints that the viewport's signals, the deformer's
// ConstraintSet and the session file carry. The app's only conversions between the two forms. Cost: O(k).

#include "spectral/vertex_ids.h"

#include <cstdint>
#include <span>
#include <vector>

namespace sc::app {

/// Typed ids of one space from plain ints, in order; negative ints (no vertex) are dropped.
template <typename Id>
[[nodiscard]] std::vector<Id> typedIds(std::span<const int> ids) {
  std::vector<std::uint32_t> indices;
  indices.reserve(ids.size());
  for (const int id : ids) {
    if (id >= 0) indices.push_back(static_cast<std::uint32_t>(id));
  }
  return spectral::vertexIds<Id>(indices);
}

/// The plain ints of typed ids, in order (ids stay below 2³¹: meshes are indexed by int everywhere).
template <typename Tag>
[[nodiscard]] std::vector<int> intIds(std::span<const spectral::VertexId<Tag>> ids) {
  std::vector<int> out;
  out.reserve(ids.size());
  for (const spectral::VertexId<Tag> id : ids) out.push_back(static_cast<int>(id.value));
  return out;
}

}  // namespace sc::app
