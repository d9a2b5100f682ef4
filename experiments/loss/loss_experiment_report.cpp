#include "experiments/loss/loss_experiment_report.h"

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
                       {QStringLiteral("hd_max_frame"), row.hdMaxFrame},
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
                                "\n\n| loss | measured loss | level | concealment | HD max (% diag) | max at frame "
                                "| HD mean (% diag) | payload B/frame | latency p99 (ms) | frames |\n"
                                "|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const LossRow& row : rows) {
    text += QStringLiteral("| %1 | %2 | %3 | %4 | %5 | %6 | %7 | %8 | %9 | %10 |\n")
                .arg(row.loss, 0, 'f', 2)
                .arg(row.measuredLoss, 0, 'f', 3)
                .arg(levelName(row), row.concealment)
                .arg(row.hdMaxPct, 0, 'f', 4)
                .arg(row.hdMaxFrame)
                .arg(row.hdMeanPct, 0, 'f', 4)
                .arg(row.payloadBytesPerFrame, 0, 'f', 0)
                .arg(row.latencyP99Ms, 0, 'f', 2)
                .arg(row.frames);
  }
  text += lossComparisons(rows);
  if (!plotFile.isEmpty()) text += QStringLiteral("\n![Loss experiment](%1)\n").arg(plotFile);
  return text;
}

QString lossComparisons(const std::vector<LossRow>& rows) {
  const auto find = [&rows](const LossRow& like, const QString& concealment) -> const LossRow* {
    for (const LossRow& row : rows) {
      if (row.loss == like.loss && row.fullLevel == like.fullLevel && row.levelVertices == like.levelVertices &&
          row.concealment == concealment)
        return &row;
    }
    return nullptr;
  };
  const std::pair<QString, QString> pairs[] = {{QStringLiteral("hold-last"), QStringLiteral("zero-fill")},
                                               {QStringLiteral("extrapolate"), QStringLiteral("hold-last")}};
  QString text;
  for (const auto& [a, b] : pairs) {
    std::vector<QString> levels;  // first-appearance order
    for (const LossRow& row : rows) {
      if (row.concealment == a && std::find(levels.begin(), levels.end(), levelName(row)) == levels.end())
        levels.push_back(levelName(row));
    }
    for (const QString& level : levels) {
      int ratios = 0, lowerMax = 0, lowerMean = 0;
      for (const LossRow& row : rows) {
        if (row.concealment != a || levelName(row) != level || row.loss == 0.0) continue;
        const LossRow* other = find(row, b);
        if (other == nullptr) continue;
        ++ratios;
        lowerMax += row.hdMaxPct < other->hdMaxPct ? 1 : 0;
        lowerMean += row.hdMeanPct < other->hdMeanPct ? 1 : 0;
      }
      if (ratios == 0) continue;
      text += QStringLiteral("- %1 vs %2 at level %3: lower max at %4 of %5 loss ratios > 0, lower mean at %6 of %5\n")
                  .arg(a, b, level)
                  .arg(lowerMax)
                  .arg(ratios)
                  .arg(lowerMean);
    }
  }
  return text.isEmpty() ? text : QStringLiteral("\n") + text;
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
  std::vector<QString> concealments;  // one colour per concealment; the low level dashed
  for (const auto& [label, points] : curves) {
    const QString concealment = points.front()->concealment;
    auto at = std::find(concealments.begin(), concealments.end(), concealment);
    if (at == concealments.end()) at = concealments.insert(concealments.end(), concealment);
    const QColor color = palette[static_cast<std::size_t>(at - concealments.begin()) % std::size(palette)];
    report::PlotSeries maxSeries{label, color, !points.front()->fullLevel, {}, {}};
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
