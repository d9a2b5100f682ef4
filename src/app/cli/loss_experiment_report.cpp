#include "app/cli/loss_experiment_report.h"

#include <QJsonObject>
#include <QJsonValue>

#include <algorithm>
#include <iterator>
#include <utility>

namespace sc::app {
namespace {

QString levelName(const LossRow& row) {
  return row.fullLevel ? QStringLiteral("full") : QString::number(row.levelVertices);
}

}  // namespace

QJsonArray lossRowsJson(const std::vector<LossRow>& rows) {
  QJsonArray array;
  for (const LossRow& row : rows) {
    QJsonObject object{{QStringLiteral("loss"), row.loss},
                       {QStringLiteral("concealment"), row.concealment},
                       {QStringLiteral("measured_loss"), row.measuredLoss},
                       {QStringLiteral("hd_max_pct"), row.hdMaxPct},
                       {QStringLiteral("hd_mean_pct"), row.hdMeanPct},
                       {QStringLiteral("payload_bytes_per_frame"), row.payloadBytesPerFrame},
                       {QStringLiteral("latency_p99_ms"), row.latencyP99Ms},
                       {QStringLiteral("frames"), row.frames},
                       {QStringLiteral("level_vertices"), row.levelVertices}};
    object.insert(QStringLiteral("level"),
                  row.fullLevel ? QJsonValue(QStringLiteral("full")) : QJsonValue(row.levelVertices));
    array.append(object);
  }
  return array;
}

QString lossRowsMarkdown(const std::vector<LossRow>& rows, const QString& preamble, const QString& plotFile) {
  QString text = preamble + QStringLiteral(
                                "\n\n| loss | measured loss | level | concealment | HD max (% diag) | HD mean (% diag) "
                                "| payload B/frame | latency p99 (ms) | frames |\n"
                                "|---:|---:|---:|---|---:|---:|---:|---:|---:|\n");
  for (const LossRow& row : rows) {
    text += QStringLiteral("| %1 | %2 | %3 | %4 | %5 | %6 | %7 | %8 | %9 |\n")
                .arg(row.loss, 0, 'f', 2)
                .arg(row.measuredLoss, 0, 'f', 3)
                .arg(levelName(row), row.concealment)
                .arg(row.hdMaxPct, 0, 'f', 4)
                .arg(row.hdMeanPct, 0, 'f', 4)
                .arg(row.payloadBytesPerFrame, 0, 'f', 0)
                .arg(row.latencyP99Ms, 0, 'f', 2)
                .arg(row.frames);
  }
  if (!plotFile.isEmpty()) text += QStringLiteral("\n![Loss experiment](%1)\n").arg(plotFile);
  return text;
}

std::vector<report::PlotPanel> lossPlotPanels(const std::vector<LossRow>& rows) {
  // One curve per (level, concealment), in first-appearance order.
  std::vector<std::pair<QString, std::vector<const LossRow*>>> curves;
  for (const LossRow& row : rows) {
    const QString key = levelName(row) + QStringLiteral(" · ") + row.concealment;
    auto it = std::find_if(curves.begin(), curves.end(), [&](const auto& c) { return c.first == key; });
    if (it == curves.end()) {
      curves.push_back({key, {}});
      it = std::prev(curves.end());
    }
    it->second.push_back(&row);
  }
  const QColor palette[] = {QColor(31, 119, 180), QColor(214, 39, 40), QColor(44, 160, 44), QColor(148, 103, 189)};
  report::PlotPanel maxPanel{QStringLiteral("Max Hausdorff distortion"),
                             QStringLiteral("loss ratio"),
                             QStringLiteral("% of bbox diagonal"),
                             {}};
  report::PlotPanel meanPanel{QStringLiteral("Mean Hausdorff distortion"),
                              QStringLiteral("loss ratio"),
                              QStringLiteral("% of bbox diagonal"),
                              {}};
  std::vector<QString> levels;  // one colour per level; zero-fill dashed
  for (const auto& [label, points] : curves) {
    const QString level = levelName(*points.front());
    auto at = std::find(levels.begin(), levels.end(), level);
    if (at == levels.end()) at = levels.insert(levels.end(), level);
    const QColor color = palette[static_cast<std::size_t>(at - levels.begin()) % 4];
    report::PlotSeries maxSeries{label, color, points.front()->concealment != QLatin1String("hold-last"), {}, {}};
    report::PlotSeries meanSeries = maxSeries;
    for (const LossRow* row : points) {
      maxSeries.x.push_back(row->loss);
      maxSeries.y.push_back(row->hdMaxPct);
      meanSeries.x.push_back(row->loss);
      meanSeries.y.push_back(row->hdMeanPct);
    }
    maxPanel.series.push_back(std::move(maxSeries));
    meanPanel.series.push_back(std::move(meanSeries));
  }
  return {maxPanel, meanPanel};
}

}  // namespace sc::app
