#include "app/gui/saved_constraints.h"

#include "app/gui/vertex_id_lists.h"

#include <algorithm>

namespace sc::app {
namespace {

std::vector<int> sortedUnique(std::vector<int> ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace

model::SavedConstraints toSavedConstraints(const HostConstraints& state) {
  model::SavedConstraints saved{sortedUnique(intIds<spectral::FullVertexTag>(state.handle)),
                                sortedUnique(intIds<spectral::FullVertexTag>(state.anchors))};
  std::erase_if(saved.anchors,
                [&saved](int id) { return std::binary_search(saved.handle.begin(), saved.handle.end(), id); });
  return saved;
}

HostConstraints toHostConstraints(const model::SavedConstraints& state) {
  return {typedIds<spectral::FullVertexId>(state.handle), typedIds<spectral::FullVertexId>(state.anchors)};
}

}  // namespace sc::app
