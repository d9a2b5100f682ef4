#pragma once
// AdaptiveResolution: the internal render scale of MeshViewport's interactive frames on a software rasteriser,
// chosen from measured paint times so that a frame stays within a time budget. Pure logic, no GL.

#include <array>
#include <cstddef>

namespace sc::app {

/// Picks the render scale (fraction of the widget's pixel width and height) of interactive frames: after a frame
/// drawn at scale s took t ms, the next frames use the largest of kScales whose predicted cost t·(s'/s)² (cost
/// proportional to the pixel count) fits the budget; it steps back up one scale at a time while the prediction
/// stays under kRaiseFraction of the budget. The per-triangle work does not shrink with the scale, so the model
/// is optimistic when stepping down; the next frames correct it (a frame over budget always steps down once more).
class AdaptiveResolution {
 public:
  /// The scales, full quality first; the last is the floor (a quarter of the pixels at most: ~0.35² ≈ 1/8).
  static constexpr std::array<double, 7> kScales = {1.0, 0.85, 0.71, 0.6, 0.5, 0.42, 0.35};
  /// Step up only when the next larger scale is predicted to cost less than this fraction of the budget.
  static constexpr double kRaiseFraction = 0.7;

  /// @param budgetMs  paint time to stay within, ms (> 0).
  explicit AdaptiveResolution(double budgetMs) : m_budgetMs(budgetMs) {}

  /// The scale for the next interactive frame (one of kScales).
  [[nodiscard]] double scale() const { return kScales[static_cast<std::size_t>(m_level)]; }
  [[nodiscard]] double budgetMs() const { return m_budgetMs; }

  /// Records that a frame drawn at `scale` (in (0, 1]) took `ms` and adapts scale(). Non-positive or non-finite
  /// values are ignored. Cost: O(kScales.size()).
  void record(double scale, double ms);

  /// Back to full quality (e.g. a new mesh).
  void reset() { m_level = 0; }

 private:
  double m_budgetMs;
  int m_level = 0;
};

}  // namespace sc::app
