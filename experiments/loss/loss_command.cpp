#include "app/cli/experiment_command.h"

#include "app/cli/load_experiment.h"
#include "app/cli/loss_experiment.h"
#include "app/cli/session_setup.h"
#include "app/report/line_plot.h"
#include "app/report/machine_info.h"
#include "app/report/markdown_section.h"

#include <QDir>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTextStream>

namespace sc::app {
namespace {

/// `--mesh MESH` (the spelling) becomes the parser's MESH positional argument; default: the 23k dragon.
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

std::optional<std::vector<double>> parseLosses(const QString& text) {
  std::vector<double> losses;
  for (const QString& part : text.split(QLatin1Char(','), Qt::SkipEmptyParts)) {
    bool ok = false;
    const double loss = part.trimmed().toDouble(&ok);
    if (!ok || loss < 0.0 || loss >= 1.0) return std::nullopt;
    losses.push_back(loss);
  }
  if (losses.empty()) return std::nullopt;
  return losses;
}

}  // namespace

int runExperimentCommand(const QStringList& arguments) {
  if (!arguments.isEmpty() && arguments.constFirst() == QLatin1String("load")) {
    return runLoadExperimentCommand(withMeshPositional(arguments.mid(1)));
  }
  if (!arguments.isEmpty() && arguments.constFirst() == QLatin1String("load-host")) {
    return runLoadHost(arguments.mid(1));  // the load experiment's host child (MESH given positionally)
  }
  if (arguments.isEmpty() || arguments.constFirst() != QLatin1String("loss")) {
    QTextStream(stderr) << "usage: shapecast-cli experiment loss|load [--mesh MESH] [options]; see --help\n";
    return kExitUsage;
  }
  SubcommandParser command(QStringLiteral("experiment loss"),
                           QStringLiteral("Loss experiment (the paper's Figures 3 and 4) on loopback."));
  QCommandLineParser& p = command.parser();
  const QCommandLineOption losses(QStringLiteral("loss"), QStringLiteral("loss ratios, comma-separated"),
                                  QStringLiteral("list"), QStringLiteral("0,0.02,0.05,0.1,0.2,0.3,0.5"));
  const QCommandLineOption burst(QStringLiteral("burst"), QStringLiteral("Gilbert-Elliott burst loss"));
  const QCommandLineOption burstLength(QStringLiteral("burst-length"),
                                       QStringLiteral("mean burst length in datagrams (default 3)"),
                                       QStringLiteral("L"), QStringLiteral("3"));
  const QCommandLineOption seed(QStringLiteral("seed"), QStringLiteral("impairment seed (default 1)"),
                                QStringLiteral("S"), QStringLiteral("1"));
  const QCommandLineOption lowFraction(QStringLiteral("low-fraction"),
                                       QStringLiteral("low level: fraction of the vertices (default 0.05)"),
                                       QStringLiteral("f"), QStringLiteral("0.05"));
  const QCommandLineOption markdown(QStringLiteral("markdown"), QStringLiteral("Markdown file to update (\"\": none)"),
                                    QStringLiteral("file"), QStringLiteral(SHAPECAST_SOURCE_DIR "/docs/benchmarks.md"));
  const QCommandLineOption plot(QStringLiteral("plot"), QStringLiteral("PNG plot (\"\": none)"), QStringLiteral("file"),
                                QStringLiteral(SHAPECAST_SOURCE_DIR "/docs/loss-experiment.png"));
  p.addOptions({losses, burst, burstLength, seed, lowFraction, markdown, plot});
  int exitCode = kExitOk;
  if (!command.parse(withMeshPositional(arguments.mid(1)), exitCode)) return exitCode;

  LossExperimentSettings settings;
  bool ok = false, ok2 = false, ok3 = false;
  const std::optional<std::vector<double>> lossList = parseLosses(p.value(losses));
  settings.burst = p.isSet(burst);
  settings.burstLength = p.value(burstLength).toDouble(&ok);
  settings.seed = p.value(seed).toULongLong(&ok2);
  settings.lowFraction = p.value(lowFraction).toDouble(&ok3);
  if (!lossList || !ok || !ok2 || !ok3 || settings.burstLength < 1.0 || settings.lowFraction <= 0.0 ||
      settings.lowFraction >= 1.0) {
    command.error(QStringLiteral(
        "--loss takes ratios in [0, 1), --burst-length ≥ 1, --low-fraction in (0, 1), --seed an integer"));
    return kExitUsage;
  }
  settings.losses = *lossList;

  const std::shared_ptr<const session::HostModel> model = loadHostModel(command, command.meshPath(), exitCode);
  if (!model) return exitCode;
  const bool json = command.basisArguments().json;
  const auto progress = [json](const QString& line) {
    if (!json) QTextStream(stderr) << line << '\n';
  };
  const std::variant<std::vector<LossRow>, QString> result = runLossExperiment(model, settings, progress);
  if (const QString* error = std::get_if<QString>(&result)) {
    command.error(*error);
    return kExitNetwork;
  }
  const std::vector<LossRow>& rows = std::get<std::vector<LossRow>>(result);

  const QString markdownFile = p.value(markdown);
  QString plotFile = p.value(plot);
  if (settings.burst && !p.isSet(plot)) plotFile.replace(QStringLiteral(".png"), QStringLiteral("-burst.png"));
  if (!plotFile.isEmpty() && !report::renderLinePlots(lossPlotPanels(rows)).save(plotFile)) {
    command.error(QStringLiteral("cannot write the plot '%1'").arg(plotFile));
    return kExitUsage;
  }
  const QString preamble =
      QStringLiteral(
          "## Loss experiment (the paper's Figures 3 and 4), on this machine\n\n"
          "Generated by `shapecast-cli experiment loss%1` on %2. Mesh `%3` (%4 vertices, m = %5); a real host and "
          "real clients on loopback (UDP + TCP sockets), %6 loss on each client's receive path (seed %7). The drag "
          "moves a handle sphere of 5% of the bbox diagonal by 15% of the diagonal over 3 s at 30 fps and back; "
          "anchors: everything farther than 40%. Distortion: vertex-set Hausdorff distance between what the client "
          "displayed for each frame and the exact frame at its own resolution, in % of the full rest bbox "
          "diagonal. Latency: from the drag command's arrival at the host to the decoded datagram at the client. "
          "Concealment of what did not arrive: hold-last (rows keep their last value), zero-fill (rows fall back "
          "to 0, the paper's way), extrapolate (hold-last + dead reckoning: missing rows and, when the next frame "
          "is 1.5 intervals overdue, whole frames predicted as Z_k + j·(Z_k − Z_k−1), at most 4 frames, then "
          "withdrawn; the predicted frames are what the distortion measures for those frames).")
          .arg(settings.burst ? QStringLiteral(" --burst") : QString(), report::machineDescription(),
               QFileInfo(command.meshPath()).fileName())
          .arg(model->vertexCount())
          .arg(model->rowCount())
          .arg(settings.burst ? QStringLiteral("Gilbert-Elliott burst (mean length %1)").arg(settings.burstLength)
                              : QStringLiteral("Bernoulli"))
          .arg(settings.seed);
  const QString plotLink = plotFile.isEmpty() || markdownFile.isEmpty()
                               ? QString()
                               : QFileInfo(markdownFile).dir().relativeFilePath(QFileInfo(plotFile).absoluteFilePath());
  const QString body = lossRowsMarkdown(rows, preamble, plotLink);
  if (json) {
    QTextStream(stdout)
        << QJsonDocument(QJsonObject{{QStringLiteral("rows"), lossRowsJson(rows)}}).toJson(QJsonDocument::Compact)
        << '\n';
  } else {
    QTextStream(stdout) << body;
  }
  const QString section = settings.burst ? QStringLiteral("loss-experiment-burst") : QStringLiteral("loss-experiment");
  if (!markdownFile.isEmpty() && !report::writeMarkdownSection(markdownFile, section, body)) {
    command.error(QStringLiteral("cannot write '%1'").arg(markdownFile));
    return kExitUsage;
  }
  return kExitOk;
}

}  // namespace sc::app
