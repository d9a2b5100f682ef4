#include "session/engine/constraint_work.h"

#include <cmath>

namespace sc::session {

std::size_t maxConstraintIds(int rows, double maxWork) {
  const double m = static_cast<double>(std::max(rows, 1));
  return static_cast<std::size_t>(std::floor(std::max(maxWork, 0.0) / (m * m)));
}

std::size_t anchorStride(std::size_t handleIds, std::size_t anchors, std::size_t maxIds) {
  if (handleIds + anchors <= maxIds) return 1;
  if (handleIds >= maxIds) return 0;
  const std::size_t room = maxIds - handleIds;
  return (anchors + room - 1) / room;  // ⌈anchors / room⌉: then ⌈anchors / k⌉ ≤ room
}

}  // namespace sc::session
