#pragma once
// A small line chart rendered to a PNG with QPainter (for generated benchmark pages such as the loss experiment
// in docs/benchmarks.md). Needs a QGuiApplication (fonts); headless runs use QT_QPA_PLATFORM=offscreen.

#include <QColor>
#include <QImage>
#include <QString>

#include <vector>

namespace sc::report {

struct PlotSeries {
  QString label;
  QColor color;
  bool dashed = false;
  std::vector<double> x;  ///< same length as y
  std::vector<double> y;
};

struct PlotPanel {
  QString title;
  QString xLabel;
  QString yLabel;
  std::vector<PlotSeries> series;
};

/// Renders the panels side by side (each with axes from 0 to the data's maximum, rounded up to a nice step, ticks
/// and a legend), `panelWidth` by `height` pixels each. Empty series are skipped. Cost: O(points).
QImage renderLinePlots(const std::vector<PlotPanel>& panels, int panelWidth = 560, int height = 420);

}  // namespace sc::report
