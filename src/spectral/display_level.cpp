#include "spectral/display_level.h"

#include "spectral/reconstruction_kernel.h"

#include <algorithm>
#include <cassert>
#include <utility>

namespace sc::spectral {

SharedDisplayLevel makeDisplayLevel(ResolutionLevel level) {
  auto display = std::make_shared<DisplayLevel>();
  display->rest = interleavedPositions(level.restV);
  display->level = std::move(level);
  return display;
}

void reconstruct(const DisplayLevel& level, const DisplayFrame& frame, std::span<float> out, int threads) {
  assert(out.size() == level.rest.size());
  if (frame.Z.size() == 0) {
    std::copy(level.rest.begin(), level.rest.end(), out.begin());
    return;
  }
  reconstructInterleaved(level.level.K, level.rest, frame.Z, out, threads);
}

std::vector<float> reconstructed(const DisplayLevel& level, const DisplayFrame& frame, int threads) {
  std::vector<float> out(level.rest.size());
  reconstruct(level, frame, out, threads);
  return out;
}

}  // namespace sc::spectral
