#include "experiments/lab_command.h"

#include "app/cli/cli_common.h"
#include "experiments/fanout/fanout_experiment.h"
#include "experiments/join/join_experiment.h"
#include "experiments/join/join_plot.h"
#include "experiments/load/load_experiment.h"
#include "experiments/loss/loss_command.h"
#include "experiments/table1/table1_command.h"

#include <QTextStream>

namespace sc::app {
namespace {

constexpr const char* kUsage =
    "usage: shapecast-lab <subcommand> [options]\n"
    "\n"
    "subcommands (the paper's experiments and benchmarks; also run as 'shapecast-cli experiment loss|load' and\n"
    "'shapecast-cli bench table1'):\n"
    "  loss [--mesh MESH] [--loss 0,0.02,...] [--burst] [--json]\n"
    "      reproduce the paper's Figures 3 and 4 on loopback and write them to docs/benchmarks.md\n"
    "  load --clients N --seconds T [--mesh MESH] [--markdown FILE] [--json]\n"
    "      one host process, N headless clients and a 30 fps drag: host CPU, per-client loss and latency\n"
    "  join [--mesh MESH] [--rate-mbit 20] [--delay-ms 20] [--loss 0] [--level full|N] [--json]\n"
    "      one host process and one client over an emulated link: bytes, time to the level and to the first\n"
    "      deformed frame, the client's peak memory\n"
    "  join-plot OUT.png RESULT.json...\n"
    "      plot join results (one `join --json` object per file) against the link rate, one line per mesh\n"
    "  fanout --viewers N --seconds T [--mesh MESH] [--viewers-per-process 100] [--json]\n"
    "      a host relaying through a local nats-server to N headless viewers (sharing processes): per-viewer\n"
    "      delivery and latency, host CPU and bytes published per frame, the server's CPU\n"
    "  table1 [MESH...] [--m 100] [--low-fraction 0.05] [--frames 200] [--json] [--markdown FILE]\n"
    "      reproduce the paper's Table 1 on this machine and write it to docs/benchmarks.md\n"
    "\n"
    "run 'shapecast-lab <subcommand> --help' for the options of a subcommand\n";

/// Drops the historical group word: "experiment loss" → "loss", "bench table1" → "table1".
QStringList withoutGroup(QStringList arguments) {
  if (arguments.size() >= 2 &&
      (arguments.constFirst() == QLatin1String("experiment") ||
       (arguments.constFirst() == QLatin1String("bench") && arguments.at(1) == QLatin1String("table1")))) {
    arguments.removeFirst();
  }
  return arguments;
}

}  // namespace

QStringList withMeshPositional(QStringList arguments) {
  QString mesh = QStringLiteral(SHAPECAST_ASSETS_DIR "/dragon_vrip_res3.ply");
  for (qsizetype i = 0; i < arguments.size(); ++i) {
    if (arguments[i] == QLatin1String("--mesh") && i + 1 < arguments.size()) {
      mesh = arguments[i + 1];
      arguments.remove(i, 2);
      break;
    }
    if (arguments[i].startsWith(QLatin1String("--mesh="))) {
      mesh = arguments[i].mid(7);
      arguments.remove(i);
      break;
    }
  }
  return arguments << mesh;
}

bool labCommandNeedsGui(const QStringList& arguments) {
  const QStringList command = withoutGroup(arguments);
  return !command.isEmpty() && command.constFirst() != QLatin1String("table1");
}

int runLabCommand(QStringList arguments) {
  const bool experimentGroup = !arguments.isEmpty() && arguments.constFirst() == QLatin1String("experiment");
  arguments = withoutGroup(std::move(arguments));
  const QString subcommand = arguments.isEmpty() ? QString() : arguments.takeFirst();
  if (subcommand == QLatin1String("loss")) return runLossCommand(withMeshPositional(arguments));
  if (subcommand == QLatin1String("load")) return runLoadExperimentCommand(withMeshPositional(arguments));
  if (subcommand == QLatin1String("join")) return runJoinExperimentCommand(withMeshPositional(arguments));
  if (subcommand == QLatin1String("join-plot")) return runJoinPlotCommand(arguments);
  if (subcommand == QLatin1String("fanout")) return runFanoutExperimentCommand(withMeshPositional(arguments));
  if (subcommand == QLatin1String("load-host")) return runLoadHost(arguments);            // the load experiment's child
  if (subcommand == QLatin1String("fanout-viewers")) return runFanoutViewers(arguments);  // the fan-out's child
  if (subcommand == QLatin1String("table1")) return runTable1Command(arguments);

  if (experimentGroup) {  // `shapecast-cli experiment` with no or an unknown experiment: its historical message
    QTextStream(stderr) << "usage: shapecast-cli experiment loss|load [--mesh MESH] [options]; see --help\n";
    return kExitUsage;
  }
  if (subcommand == QLatin1String("--help") || subcommand == QLatin1String("-h")) {
    QTextStream(stdout) << kUsage;
    return kExitOk;
  }
  QTextStream err(stderr);
  if (!subcommand.isEmpty()) err << "shapecast-lab: unknown subcommand '" << subcommand << "'\n\n";
  err << kUsage;
  return kExitUsage;
}

}  // namespace sc::app
