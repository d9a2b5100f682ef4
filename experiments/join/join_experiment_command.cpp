// `shapecast-lab join`: options, the run, and its one-line or JSON report (see join_experiment.h).

#include "experiments/join/join_experiment.h"
#include "experiments/load/host_child.h"
#include "experiments/report/machine_info.h"

#include <QCoreApplication>
#include <QJsonDocument>
#include <QTextStream>

#include <cmath>

namespace sc::app {

int runJoinExperimentCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("experiment join"),
                           QStringLiteral("Join experiment: a host process and one client over an emulated link."));
  QCommandLineParser& p = command.parser();
  const QCommandLineOption rate(QStringLiteral("rate-mbit"), QStringLiteral("link rate, Mbit/s (0 = unlimited)"),
                                QStringLiteral("R"), QStringLiteral("20"));
  const QCommandLineOption delay(QStringLiteral("delay-ms"), QStringLiteral("one-way delay of the datagrams, ms"),
                                 QStringLiteral("D"), QStringLiteral("20"));
  const QCommandLineOption loss(QStringLiteral("loss"), QStringLiteral("datagram loss ratio, 0..1"),
                                QStringLiteral("P"), QStringLiteral("0"));
  const QCommandLineOption level(QStringLiteral("level"), QStringLiteral("requested level: full or N vertices"),
                                 QStringLiteral("full|N"), QStringLiteral("full"));
  const QCommandLineOption timeout(QStringLiteral("timeout"),
                                   QStringLiteral("give up after T seconds without a deformed frame (default 1800)"),
                                   QStringLiteral("T"), QStringLiteral("1800"));
  const QCommandLineOption direct(QStringLiteral("no-progressive"),
                                  QStringLiteral("ask for the requested level only (no smallest level first)"));
  p.addOptions({rate, delay, loss, level, timeout, direct});
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;

  JoinExperimentSettings settings;
  bool ok1 = false, ok2 = false, ok3 = false, ok4 = true, ok5 = false;
  settings.timeoutSeconds = p.value(timeout).toDouble(&ok5);
  settings.rateMbit = p.value(rate).toDouble(&ok1);
  settings.delayMs = p.value(delay).toInt(&ok2);
  settings.loss = p.value(loss).toDouble(&ok3);
  if (p.value(level) != QLatin1String("full")) settings.level = p.value(level).toUInt(&ok4);
  if (!ok1 || !ok2 || !ok3 || !ok4 || !ok5 || !(settings.timeoutSeconds > 0.0) || !(settings.rateMbit >= 0.0) ||
      settings.delayMs < 0 || !(settings.loss >= 0.0) || settings.loss > 1.0) {
    command.error(QStringLiteral(
        "--rate-mbit takes Mbit/s ≥ 0, --delay-ms ms ≥ 0, --loss 0..1, --level full or N, --timeout T > 0"));
    return kExitUsage;
  }
  settings.progressive = !p.isSet(direct);
  const QStringList basis = hostChildBasisArguments(command.basisArguments());
  const bool json = command.basisArguments().json;
  const auto progress = progressPrinter(json);
  const std::variant<JoinResult, QString> outcome =
      runJoinExperiment(QCoreApplication::applicationFilePath(), command.meshPath(), basis, settings, progress);
  if (const QString* error = std::get_if<QString>(&outcome)) {
    command.error(*error);
    return kExitNetwork;
  }
  const JoinResult& r = std::get<JoinResult>(outcome);
  if (json) {
    QJsonObject object = joinResultJson(r);
    object.insert(QStringLiteral("machine"), report::machineDescription());
    QTextStream(stdout) << QJsonDocument(object).toJson(QJsonDocument::Compact) << '\n';
    return kExitOk;
  }
  QTextStream(stdout) << QStringLiteral(
                             "%1 (%2 vertices, m = %3), level %4 vertices, %5 Mbit/s, %6 ms, loss %7: %8 MB "
                             "received, level ready %9 s (transfer at %10 Mbit/s), first deformed frame %11 s (on "
                             "%14 vertices, shown at %15 s), peak RSS %12 MiB (%13 MiB before joining)\n")
                             .arg(r.mesh)
                             .arg(r.vertices)
                             .arg(r.rows)
                             .arg(r.levelVertices)
                             .arg(r.settings.rateMbit)
                             .arg(r.settings.delayMs)
                             .arg(r.settings.loss)
                             .arg(static_cast<double>(r.streamBytes + r.datagramBytes) / 1e6, 0, 'f', 2)
                             .arg(r.levelReadySeconds, 0, 'f', 2)
                             .arg(r.transferMbit, 0, 'f', 2)
                             .arg(r.firstFrameSeconds, 0, 'f', 2)
                             .arg(r.peakRssMb, 0, 'f', 0)
                             .arg(r.baselineRssMb, 0, 'f', 0)
                             .arg(r.firstLevelVertices)
                             .arg(r.firstLevelSeconds, 0, 'f', 2);
  return kExitOk;
}

}  // namespace sc::app
