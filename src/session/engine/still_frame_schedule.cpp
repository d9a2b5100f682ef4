#include "session/engine/still_frame_schedule.h"

#include <algorithm>
#include <cmath>

namespace sc::session {

std::optional<Micros> StillFrameSchedule::onFrame(Micros at, bool moved) {
  if (!moved) {
    m_lastMoved = false;
    return std::nullopt;
  }
  if (m_lastMoved) {
    const Micros sample = at - m_lastMovedAt;
    if (sample >= kMinSample && sample <= kMaxSample) {
      m_interval = m_interval == Micros{0} ? sample : m_interval + (sample - m_interval) / 8;
    }
  }
  m_lastMoved = true;
  m_lastMovedAt = at;
  return at + delay();
}

Micros StillFrameSchedule::delay() const {
  if (m_interval == Micros{0}) return kMaxDelay;
  const Micros scaled{std::llround(kDelayFactor * static_cast<double>(m_interval.count()))};
  return std::clamp(scaled, kMinDelay, kMaxDelay);
}

}  // namespace sc::session
