#include "experiments/report/line_plot.h"

#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>
#include <vector>

namespace sc::report {
namespace {

/// The smallest "nice" step (1, 2 or 5 × 10^k) that splits [0, maximum] into at most `ticks` intervals.
double niceStep(double maximum, int ticks) {
  if (!(maximum > 0.0)) return 1.0;
  const double raw = maximum / ticks;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0, 10.0}) {
    if (factor * magnitude >= raw) return factor * magnitude;
  }
  return 10.0 * magnitude;
}

double seriesMaximum(const PlotPanel& panel, bool xAxis) {
  double maximum = 0.0;
  for (const PlotSeries& s : panel.series) {
    for (double v : xAxis ? s.x : s.y) {
      if (std::isfinite(v)) maximum = std::max(maximum, v);
    }
  }
  return maximum;
}

QString tickText(double value, double step) {
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step)));
  return QString::number(value, 'f', decimals);
}

void drawPanel(QPainter& painter, const PlotPanel& panel, const QRect& area) {
  const QRect plot = area.adjusted(70, 40, -20, -55);
  const double xStep = niceStep(seriesMaximum(panel, true), 5);
  // Head room above the data for the legend box (top left), so no curve runs under it.
  const double yData = seriesMaximum(panel, false) * 1.4;
  const double yStep = niceStep(yData, 5);
  const double xMax = std::max(xStep, std::ceil(seriesMaximum(panel, true) / xStep) * xStep);
  const double yMax = std::max(yStep, std::ceil(yData / yStep) * yStep);
  const auto toPixel = [&](double x, double y) {
    return QPointF(plot.left() + x / xMax * plot.width(), plot.bottom() - y / yMax * plot.height());
  };

  painter.setPen(Qt::black);
  QFont titleFont = painter.font();
  titleFont.setBold(true);
  painter.setFont(titleFont);
  painter.drawText(QRect(area.left(), area.top() + 8, area.width(), 24), Qt::AlignHCenter, panel.title);
  painter.setFont(QFont());

  for (double y = 0.0; y <= yMax + 1e-12; y += yStep) {
    const QPointF p = toPixel(0.0, y);
    painter.setPen(QColor(225, 225, 225));
    painter.drawLine(QPointF(plot.left(), p.y()), QPointF(plot.right(), p.y()));
    painter.setPen(Qt::black);
    painter.drawText(QRectF(plot.left() - 66, p.y() - 10, 60, 20), Qt::AlignRight | Qt::AlignVCenter,
                     tickText(y, yStep));
  }
  for (double x = 0.0; x <= xMax + 1e-12; x += xStep) {
    const QPointF p = toPixel(x, 0.0);
    painter.drawText(QRectF(p.x() - 30, plot.bottom() + 4, 60, 20), Qt::AlignHCenter, tickText(x, xStep));
  }
  painter.drawRect(plot);
  painter.drawText(QRect(plot.left(), plot.bottom() + 26, plot.width(), 22), Qt::AlignHCenter, panel.xLabel);
  painter.save();
  painter.translate(area.left() + 14, plot.center().y());
  painter.rotate(-90);
  painter.drawText(QRect(-plot.height() / 2, -10, plot.height(), 22), Qt::AlignHCenter, panel.yLabel);
  painter.restore();

  std::vector<const PlotSeries*> drawn;
  for (const PlotSeries& s : panel.series) {
    if (s.x.empty()) continue;
    drawn.push_back(&s);
    QPen pen(s.color, 2.0);
    if (s.dashed) pen.setStyle(Qt::DashLine);
    painter.setPen(pen);
    QPainterPath path;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      const QPointF p = toPixel(s.x[i], s.y[i]);
      if (i == 0) {
        path.moveTo(p);
      } else {
        path.lineTo(p);
      }
      painter.drawEllipse(p, 2.5, 2.5);
    }
    painter.drawPath(path);
  }

  // Legend on a white box above the curves (top left of the plot).
  int legendWidth = 0;
  for (const PlotSeries* s : drawn)
    legendWidth = std::max(legendWidth, painter.fontMetrics().horizontalAdvance(s->label));
  const QRectF box(plot.left() + 6, plot.top() + 5, legendWidth + 50, 18.0 * static_cast<double>(drawn.size()) + 6);
  if (!drawn.empty()) {
    painter.setPen(QColor(200, 200, 200));
    painter.setBrush(QColor(255, 255, 255, 235));
    painter.drawRect(box);
    painter.setBrush(Qt::NoBrush);
  }
  for (std::size_t row = 0; row < drawn.size(); ++row) {
    QPen pen(drawn[row]->color, 2.0);
    if (drawn[row]->dashed) pen.setStyle(Qt::DashLine);
    painter.setPen(pen);
    const QPointF legend(box.left() + 8, box.top() + 12 + 18.0 * static_cast<double>(row));
    painter.drawLine(legend, legend + QPointF(28, 0));
    painter.setPen(Qt::black);
    painter.drawText(legend + QPointF(36, 5), drawn[row]->label);
  }
}

}  // namespace

QImage renderLinePlots(const std::vector<PlotPanel>& panels, int panelWidth, int height) {
  QImage image(panelWidth * std::max<int>(1, static_cast<int>(panels.size())), height, QImage::Format_RGB32);
  image.fill(Qt::white);
  QPainter painter(&image);
  painter.setRenderHint(QPainter::Antialiasing);
  for (std::size_t i = 0; i < panels.size(); ++i) {
    drawPanel(painter, panels[i], QRect(static_cast<int>(i) * panelWidth, 0, panelWidth, height));
  }
  return image;
}

}  // namespace sc::report
