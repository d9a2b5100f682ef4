#include "app/gui/viewport/adaptive_resolution.h"

#include <algorithm>
#include <cmath>

namespace sc::app {

namespace {

// Index of the largest scale ≤ wanted (the last one when none is).
int levelAtMost(double wanted) {
  const int last = static_cast<int>(AdaptiveResolution::kScales.size()) - 1;
  for (int level = 0; level < last; ++level) {
    if (AdaptiveResolution::kScales[static_cast<std::size_t>(level)] <= wanted) {
      return level;
    }
  }
  return last;
}

}  // namespace

void AdaptiveResolution::record(double scale, double ms) {
  if (!(ms > 0.0) || !std::isfinite(ms) || !(scale > 0.0) || scale > 1.0) {
    return;
  }
  const int last = static_cast<int>(kScales.size()) - 1;
  const bool atCurrent = std::abs(scale - this->scale()) < 1e-9;
  if (ms > m_budgetMs) {
    int down = levelAtMost(scale * std::sqrt(m_budgetMs / ms));
    if (atCurrent) {
      down = std::max(down, m_level + 1);  // the area model was optimistic: one more step at least
    }
    m_level = std::max(m_level, std::min(down, last));
    return;
  }
  if (m_level > 0) {
    const double up = kScales[static_cast<std::size_t>(m_level - 1)];
    const double predicted = ms * (up / scale) * (up / scale);
    if (predicted < kRaiseFraction * m_budgetMs) {
      --m_level;
    }
  }
}

}  // namespace sc::app
