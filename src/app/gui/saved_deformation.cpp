#include "app/gui/saved_deformation.h"

#include "app/gui/vertex_id_lists.h"

namespace sc::app {

model::SavedDeformation toSavedDeformation(const HostDeformation& state) {
  return {intIds<spectral::FullVertexTag>(state.handle), intIds<spectral::FullVertexTag>(state.anchors),
          state.translation, state.rotation};
}

HostDeformation toHostDeformation(const model::SavedDeformation& state) {
  return {typedIds<spectral::FullVertexId>(state.handle), typedIds<spectral::FullVertexId>(state.anchors),
          state.translation, state.rotation};
}

}  // namespace sc::app
