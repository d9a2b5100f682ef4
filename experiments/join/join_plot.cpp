#include "experiments/join/join_plot.h"

#include "app/cli/cli_common.h"

#include <QFile>
#include <QFileInfo>
#include <QJsonDocument>
#include <QTextStream>

#include <algorithm>
#include <array>
#include <map>

namespace sc::app {
namespace {

struct JoinPoint {
  double rate = 0.0;
  QJsonObject result;
};

const std::array<QColor, 4> kColors = {QColor(31, 119, 180), QColor(214, 39, 40), QColor(44, 160, 44),
                                       QColor(148, 103, 189)};

}  // namespace

std::vector<report::PlotPanel> joinPlotPanels(const std::vector<QJsonObject>& results) {
  std::map<QString, std::vector<JoinPoint>> byMesh;
  for (const QJsonObject& r : results) {
    const QString mesh = QFileInfo(r.value(QStringLiteral("mesh")).toString()).fileName();
    if (mesh.isEmpty() || !r.value(QStringLiteral("rate_mbit")).isDouble()) continue;
    byMesh[mesh].push_back({r.value(QStringLiteral("rate_mbit")).toDouble(), r});
  }
  std::vector<report::PlotPanel> panels = {
      {QStringLiteral("First deformed frame"), QStringLiteral("link rate (Mbit/s)"), QStringLiteral("s"), {}},
      {QStringLiteral("Requested level ready"), QStringLiteral("link rate (Mbit/s)"), QStringLiteral("s"), {}},
      {QStringLiteral("Bytes received"), QStringLiteral("link rate (Mbit/s)"), QStringLiteral("MB"), {}}};
  std::size_t colour = 0;
  for (auto& [mesh, points] : byMesh) {
    std::sort(points.begin(), points.end(), [](const JoinPoint& a, const JoinPoint& b) { return a.rate < b.rate; });
    const QColor color = kColors[colour++ % kColors.size()];
    std::array<report::PlotSeries, 3> series;
    for (report::PlotSeries& s : series) {
      s.label = mesh;
      s.color = color;
    }
    for (const JoinPoint& p : points) {
      const QJsonValue first = p.result.value(QStringLiteral("first_frame_s"));
      if (first.isDouble()) {
        series[0].x.push_back(p.rate);
        series[0].y.push_back(first.toDouble());
      }
      series[1].x.push_back(p.rate);
      series[1].y.push_back(p.result.value(QStringLiteral("level_ready_s")).toDouble());
      series[2].x.push_back(p.rate);
      series[2].y.push_back(p.result.value(QStringLiteral("bytes_received")).toDouble() / 1e6);
    }
    for (std::size_t i = 0; i < series.size(); ++i) panels[i].series.push_back(std::move(series[i]));
  }
  return panels;
}

int runJoinPlotCommand(const QStringList& arguments) {
  QTextStream err(stderr);
  if (arguments.size() < 2 || arguments.constFirst().startsWith(QLatin1Char('-'))) {
    err << "usage: shapecast-lab join-plot OUT.png RESULT.json...  (each file: one `shapecast-lab join --json`)\n";
    return kExitUsage;
  }
  std::vector<QJsonObject> results;
  for (const QString& path : arguments.mid(1)) {
    QFile file(path);
    if (!file.open(QIODevice::ReadOnly)) {
      err << "shapecast-lab join-plot: cannot read " << path << '\n';
      return kExitUsage;
    }
    const QJsonDocument document = QJsonDocument::fromJson(file.read(1 << 20));
    if (!document.isObject()) {
      err << "shapecast-lab join-plot: " << path << " is not one JSON object\n";
      return kExitUsage;
    }
    results.push_back(document.object());
  }
  const std::vector<report::PlotPanel> panels = joinPlotPanels(results);
  if (!report::renderLinePlots(panels, 420, 360).save(arguments.constFirst())) {
    err << "shapecast-lab join-plot: cannot write " << arguments.constFirst() << '\n';
    return kExitUsage;
  }
  QTextStream(stdout) << "plotted " << results.size() << " results of " << panels.front().series.size()
                      << " meshes into " << arguments.constFirst() << '\n';
  return kExitOk;
}

}  // namespace sc::app
