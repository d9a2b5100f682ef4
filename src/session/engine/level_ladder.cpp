#include "session/engine/level_ladder.h"

#include <algorithm>
#include <functional>

namespace sc::session {

LevelLadder::LevelLadder(std::uint32_t full, const std::vector<std::uint32_t>& targets) : m_full(full) {
  for (const std::uint32_t t : targets) {
    if (t < m_full && std::find(m_ladder.begin(), m_ladder.end(), t) == m_ladder.end()) m_ladder.push_back(t);
  }
  std::sort(m_ladder.begin(), m_ladder.end(), std::greater<>());
}

std::uint32_t LevelLadder::pick(std::uint32_t wanted) const {
  if (wanted == 0 || wanted >= m_full || m_ladder.empty()) return m_full;
  const auto count = [this](std::uint32_t target) {
    const LevelFigures* level = find(target);
    return level ? level->vertexCount : target;
  };
  const auto distance = [wanted](std::uint32_t v) { return v > wanted ? v - wanted : wanted - v; };
  std::uint32_t best = m_ladder.front();
  for (const std::uint32_t t : m_ladder) {
    const std::uint32_t d = distance(count(t)), bestD = distance(count(best));
    if (d < bestD || (d == bestD && count(t) > count(best))) best = t;
  }
  return best;
}

const LevelFigures* LevelLadder::find(std::uint32_t target) const {
  const auto it = m_built.find(target);
  return it == m_built.end() ? nullptr : &it->second;
}

LevelList LevelLadder::levelList() const {
  LevelList list;
  list.total = static_cast<std::uint8_t>(std::min<std::size_t>(m_ladder.size() + 1, kMaxLevels));
  for (std::size_t i = 0; i < list.total; ++i) {
    const LevelFigures* level = find(i == 0 ? m_full : m_ladder[i - 1]);
    if (level == nullptr) continue;
    list.levels.push_back(
        LevelInfo{static_cast<std::uint8_t>(i), level->vertexCount, level->faceCount, level->payloadSize});
  }
  return list;
}

}  // namespace sc::session
