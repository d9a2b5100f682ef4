#pragma once
// Results of the loss experiment (`shapecast-cli experiment loss`, the paper's Figures 3 and 4) and their three
// presentations: the --json rows, the Markdown table for docs/benchmarks.md, and the PNG plot.

#include "experiments/report/line_plot.h"

#include <QJsonArray>
#include <QString>

#include <vector>

namespace sc::app {

/// One row: one loss ratio, one concealment, one client resolution.
struct LossRow {
  double loss = 0.0;          ///< configured loss ratio
  QString concealment;        ///< "hold-last", "zero-fill" or "extrapolate"
  int levelVertices = 0;      ///< the client's vertex count
  bool fullLevel = true;      ///< true: "full"; false: the level is named by its vertex count
  double measuredLoss = 0.0;  ///< datagrams the impairment dropped / offered, during the drag
  double hdMaxPct = 0.0;      ///< normalised Hausdorff distortion over the drag's frames, % of the diagonal
  double hdMeanPct = 0.0;
  int hdMaxFrame = 0;  ///< frame of the drag (0 = its first) where the max occurred; the turn is at frames/2
  double payloadBytesPerFrame = 0;  ///< UDP payload bytes the host sent this client per frame
  double latencyP99Ms = 0.0;        ///< drag arrival at the host → datagram decoded at the client
  int frames = 0;                   ///< reference frames evaluated
};

/// The --json form: {"rows":[{loss, concealment, level ("full" or a vertex count), measured_loss, hd_max_pct,
/// hd_max_frame, hd_mean_pct, payload_bytes_per_frame, latency_p99_ms, frames, level_vertices}, …]}.
QJsonArray lossRowsJson(const std::vector<LossRow>& rows);

/// A Markdown table, one line per row, preceded by `preamble` (machine, mesh, settings) and followed by
/// lossComparisons() and a link to `plotFile` (relative to the Markdown file) when not empty.
QString lossRowsMarkdown(const std::vector<LossRow>& rows, const QString& preamble, const QString& plotFile);

/// One line per (concealment pair, level): at how many loss ratios > 0 hold-last has a strictly lower max and
/// mean than zero-fill, and extrapolate than hold-last (Markdown list; empty without such pairs).
QString lossComparisons(const std::vector<LossRow>& rows);

/// Two panels (max and mean distortion against the loss ratio), one curve per concealment and level: one colour
/// per concealment, solid at full resolution, dashed at the low level.
std::vector<report::PlotPanel> lossPlotPanels(const std::vector<LossRow>& rows);

}  // namespace sc::app
