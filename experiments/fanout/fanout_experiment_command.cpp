// `shapecast-lab fanout`: options, the run, and its one-line or JSON report (see fanout_experiment.h).

#include "experiments/fanout/fanout_experiment.h"
#include "experiments/load/host_child.h"
#include "experiments/report/machine_info.h"

#include <QCoreApplication>
#include <QJsonDocument>
#include <QTextStream>

namespace sc::app {

int runFanoutExperimentCommand(const QStringList& arguments) {
  SubcommandParser command(
      QStringLiteral("experiment fanout"),
      QStringLiteral("Fan-out experiment: a relaying host, a local nats-server and N headless viewers."));
  QCommandLineParser& p = command.parser();
  const QCommandLineOption viewers(QStringLiteral("viewers"), QStringLiteral("viewers, 1..10000"), QStringLiteral("N"),
                                   QStringLiteral("10"));
  const QCommandLineOption seconds(QStringLiteral("seconds"), QStringLiteral("drag duration, s"), QStringLiteral("T"),
                                   QStringLiteral("10"));
  const QCommandLineOption perProcess(QStringLiteral("viewers-per-process"),
                                      QStringLiteral("viewers sharing one process and its thread (default 100)"),
                                      QStringLiteral("K"), QStringLiteral("100"));
  const QCommandLineOption pending(QStringLiteral("pending"),
                                   QStringLiteral("each viewer's pending limit, frames (default 8)"),
                                   QStringLiteral("N"), QStringLiteral("8"));
  const QCommandLineOption shared(
      QStringLiteral("shared-verify"),
      QStringLiteral("the viewers of a process verify each frame's signature once between them (default: each)"));
  p.addOptions({viewers, seconds, perProcess, pending, shared});
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  FanoutExperimentSettings settings;
  bool ok1 = false, ok2 = false, ok3 = false, ok4 = false;
  settings.viewers = p.value(viewers).toInt(&ok1);
  settings.seconds = p.value(seconds).toDouble(&ok2);
  settings.viewersPerProcess = p.value(perProcess).toInt(&ok3);
  settings.pendingLimit = p.value(pending).toInt(&ok4);
  if (!ok1 || !ok2 || !ok3 || !ok4 || settings.viewers < 1 || settings.viewers > 10000 || !(settings.seconds > 0.0) ||
      settings.seconds > 3600.0 || settings.viewersPerProcess < 1 || settings.pendingLimit < 1) {
    command.error(QStringLiteral(
        "--viewers takes 1..10000, --seconds 0 < T ≤ 3600, --viewers-per-process K ≥ 1, --pending N ≥ 1"));
    return kExitUsage;
  }
  settings.sharedVerification = p.isSet(shared);
  settings.startTimeoutSeconds = 60.0 + 0.2 * settings.viewers;
  const QStringList basis = hostChildBasisArguments(command.basisArguments());
  const bool json = command.basisArguments().json;
  const std::variant<FanoutResult, QString> outcome = runFanoutExperiment(
      QCoreApplication::applicationFilePath(), command.meshPath(), basis, settings, progressPrinter(json));
  if (const QString* error = std::get_if<QString>(&outcome)) {
    command.error(*error);
    return kExitNetwork;
  }
  QJsonObject r = fanoutResultJson(std::get<FanoutResult>(outcome));
  r.insert(QStringLiteral("machine"), report::machineDescription());
  if (json) {
    QTextStream(stdout) << QJsonDocument(r).toJson(QJsonDocument::Compact) << '\n';
    return kExitOk;
  }
  const auto number = [&r](const char* key, int decimals) {
    return QString::number(r.value(QLatin1String(key)).toDouble(), 'f', decimals);
  };
  QTextStream(stdout) << QStringLiteral(
                             "%1 viewers in %2 processes, %3 frames published over %4 s: every viewer got ≥ %5 of "
                             "them (median %6); latency p50 %7 ms, p99 %8 ms (median viewer) / %9 ms (worst); host "
                             "CPU %10% of a core, %11 B published per frame; nats-server CPU %12%; viewer processes "
                             "%13% CPU, %14 threads; load average %15\n")
                             .arg(r.value(QStringLiteral("viewers")).toInt())
                             .arg(r.value(QStringLiteral("processes")).toInt())
                             .arg(r.value(QStringLiteral("frames_published")).toInteger())
                             .arg(number("drag_seconds", 1), number("min_delivered_fraction", 4),
                                  number("median_delivered_fraction", 4), number("latency_p50_ms", 1),
                                  number("latency_p99_ms_median", 1), number("latency_p99_ms", 1),
                                  number("host_cpu_pct", 1), number("host_upload_bytes_per_frame", 0),
                                  number("server_cpu_pct", 1))
                             .arg(number("viewer_processes_cpu_pct", 0))
                             .arg(r.value(QStringLiteral("viewer_threads")).toInt())
                             .arg(number("load_average", 1));
  return kExitOk;
}

}  // namespace sc::app
