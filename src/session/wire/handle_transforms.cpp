#include "session/wire/handle_transforms.h"

namespace sc::session {

HandleTransform toWire(std::uint16_t handle, const spectral::HandleTransform& pose) {
  HandleTransform out;
  out.handle = handle;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.affine[static_cast<std::size_t>(4 * r + c)] = pose.rotation(r, c);
    out.affine[static_cast<std::size_t>(4 * r + 3)] = pose.translation(r);
  }
  return out;
}

std::vector<spectral::HandleTransform> fromWire(std::span<const HandleTransform> handles, std::size_t groups) {
  std::vector<spectral::HandleTransform> poses(groups);
  for (const HandleTransform& h : handles) {
    if (h.handle >= groups) continue;
    spectral::HandleTransform& pose = poses[h.handle];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) pose.rotation(r, c) = h.affine[static_cast<std::size_t>(4 * r + c)];
      pose.translation(r) = h.affine[static_cast<std::size_t>(4 * r + 3)];
    }
  }
  return poses;
}

}  // namespace sc::session
