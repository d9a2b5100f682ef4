#pragma once
// Conversion between the deformer's handle pose (spectral::HandleTransform: rotation R about the group's rest
// centroid, then translation t) and its wire form in a Drag (session::HandleTransform: 3×4 row-major [R | t]).
// Pure; no validation beyond what the types carry (the Drag decoder already rejects non-finite values).

#include "session/wire/control_messages.h"
#include "spectral/spectral_deformer.h"

#include <span>
#include <vector>

namespace sc::session {

/// The wire form of `pose` for handle group `handle`: affine = [R | t], row-major.
HandleTransform toWire(std::uint16_t handle, const spectral::HandleTransform& pose);

/// The deformer's transforms for `groups` handle groups from a Drag's entries: group i takes the entry with
/// handle == i (the last one wins); groups without an entry stay at rest (identity); entries with handle ≥ groups
/// are ignored. Cost: O(groups + entries).
std::vector<spectral::HandleTransform> fromWire(std::span<const HandleTransform> handles, std::size_t groups);

}  // namespace sc::session
