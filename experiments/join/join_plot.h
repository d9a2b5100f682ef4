#pragma once
// `shapecast-lab join-plot OUT.png RESULT.json…` (issue 17 item 5): the join experiment's figures against the link
// rate, one line per mesh, from the JSON objects `shapecast-lab join --json` printed (one file each). Three panels:
// the first deformed frame, the requested level ready (both seconds from the TCP connect) and the bytes received
// (MB). Results without a first frame (a host that could not drag) leave that point out of the first panel.

#include "experiments/report/line_plot.h"

#include <QJsonObject>
#include <QStringList>

#include <vector>

namespace sc::app {

/// The panels for `results` (joinResultJson() objects): series by "mesh" (its file name), points by "rate_mbit",
/// sorted by rate. Objects without a mesh or a rate are skipped. Cost: O(r log r).
std::vector<report::PlotPanel> joinPlotPanels(const std::vector<QJsonObject>& results);

/// The command (arguments after "join-plot"): reads the files, writes the PNG, prints what it plotted. Exit codes:
/// cli_common.h (usage: missing arguments, an unreadable or non-object file, an unwritable image).
int runJoinPlotCommand(const QStringList& arguments);

}  // namespace sc::app
