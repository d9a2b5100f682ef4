// `shapecast-cli experiment load`: options, the run, and its report (see load_experiment.h).

#include "experiments/load/host_child.h"
#include "experiments/load/load_experiment.h"
#include "experiments/report/machine_info.h"
#include "experiments/report/markdown_section.h"
#include "session/wire/wire_format.h"

#include <QCoreApplication>
#include <QJsonDocument>
#include <QTextStream>

namespace sc::app {

int runLoadExperimentCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("experiment load"),
                           QStringLiteral("Load experiment: one host process, N headless clients, a 30 fps drag."));
  QCommandLineParser& p = command.parser();
  const QCommandLineOption clients(QStringLiteral("clients"), QStringLiteral("headless clients (default 8)"),
                                   QStringLiteral("N"), QStringLiteral("8"));
  const QCommandLineOption seconds(QStringLiteral("seconds"), QStringLiteral("drag duration (default 10)"),
                                   QStringLiteral("T"), QStringLiteral("10"));
  const QCommandLineOption fraction(QStringLiteral("client-fraction"),
                                    QStringLiteral("each client's level: fraction of the vertices (default 0.05)"),
                                    QStringLiteral("f"), QStringLiteral("0.05"));
  const QCommandLineOption threads(QStringLiteral("client-threads"),
                                   QStringLiteral("threads running the clients (default 4)"), QStringLiteral("K"),
                                   QStringLiteral("4"));
  const QCommandLineOption markdown(QStringLiteral("markdown"),
                                    QStringLiteral("Markdown file whose load-experiment section to write"),
                                    QStringLiteral("file"));
  p.addOptions({clients, seconds, fraction, threads, markdown});
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;

  LoadExperimentSettings settings;
  bool ok1 = false, ok2 = false, ok3 = false, ok4 = false;
  settings.clients = p.value(clients).toInt(&ok1);
  settings.seconds = p.value(seconds).toDouble(&ok2);
  settings.clientFraction = p.value(fraction).toDouble(&ok3);
  settings.clientThreads = p.value(threads).toInt(&ok4);
  if (!ok1 || !ok2 || !ok3 || !ok4 || settings.clients < 1 || settings.clients > session::kMaxPeers - 1 ||
      settings.seconds <= 0.0 || settings.clientFraction <= 0.0 || settings.clientFraction > 1.0 ||
      settings.clientThreads < 1) {
    command.error(QStringLiteral("--clients takes 1..%1 (the protocol's peer limit less the host), --seconds a "
                                 "positive number, --client-fraction (0, 1], --client-threads ≥ 1")
                      .arg(session::kMaxPeers - 1));
    return kExitUsage;
  }
  const QStringList basis = hostChildBasisArguments(command.basisArguments());
  const bool json = command.basisArguments().json;
  const auto progress = progressPrinter(json);
  const std::variant<LoadResult, QString> outcome =
      runLoadExperiment(QCoreApplication::applicationFilePath(), command.meshPath(), basis, settings, progress);
  if (const QString* error = std::get_if<QString>(&outcome)) {
    command.error(*error);
    return kExitNetwork;
  }
  const LoadResult& result = std::get<LoadResult>(outcome);
  const QString body = loadResultMarkdown(result, report::machineDescription());
  if (json) {
    QTextStream(stdout) << QJsonDocument(loadResultJson(result)).toJson(QJsonDocument::Compact) << '\n';
  } else {
    QTextStream(stdout) << body;
  }
  if (p.isSet(markdown) && !report::writeMarkdownSection(p.value(markdown), QStringLiteral("load-experiment"), body)) {
    command.error(QStringLiteral("cannot write '%1'").arg(p.value(markdown)));
    return kExitUsage;
  }
  return kExitOk;
}

}  // namespace sc::app
