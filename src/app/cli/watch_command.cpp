#include "app/cli/watch_command.h"

#include "app/cli/quit_on_signal.h"
#include "app/cli/relay_arguments.h"
#include "session/net/relay_viewer.h"
#include "session/net/tls_identity.h"

#include <QCoreApplication>
#include <QJsonObject>
#include <QTextStream>
#include <QTimer>

namespace sc::app {
namespace {

QJsonObject watchReport(const session::RelayViewer& viewer) {
  const session::RelayViewerStats s = viewer.stats();
  return QJsonObject{{QStringLiteral("frame"), static_cast<qint64>(viewer.receiver().frame().value_or(0))},
                     {QStringLiteral("applied"), static_cast<qint64>(s.applied)},
                     {QStringLiteral("lost"), static_cast<qint64>(s.lost)},
                     {QStringLiteral("stale"), static_cast<qint64>(s.stale)},
                     {QStringLiteral("bad_signature"), static_cast<qint64>(s.badSignature)},
                     {QStringLiteral("malformed"), static_cast<qint64>(s.malformed)},
                     {QStringLiteral("dropped_pending"), static_cast<qint64>(viewer.droppedPending())},
                     {QStringLiteral("reconnections"), viewer.connection()->reconnections()},
                     {QStringLiteral("latency_p50_ms"), s.latencyP50Ms},
                     {QStringLiteral("latency_p99_ms"), s.latencyP99Ms}};
}

QString watchLine(const QJsonObject& r) {
  return QStringLiteral(
             "frame %1: %2 applied, %3 lost, %4 stale, %5 bad signature, %6 dropped waiting, latency p50 "
             "%7 ms p99 %8 ms (last 10 s)")
      .arg(r.value(QStringLiteral("frame")).toInteger())
      .arg(r.value(QStringLiteral("applied")).toInteger())
      .arg(r.value(QStringLiteral("lost")).toInteger())
      .arg(r.value(QStringLiteral("stale")).toInteger())
      .arg(r.value(QStringLiteral("bad_signature")).toInteger())
      .arg(r.value(QStringLiteral("dropped_pending")).toInteger())
      .arg(r.value(QStringLiteral("latency_p50_ms")).toDouble(), 0, 'f', 2)
      .arg(r.value(QStringLiteral("latency_p99_ms")).toDouble(), 0, 'f', 2);
}

}  // namespace

int runWatchCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("watch"),
                           QStringLiteral("Watch a relayed session through NATS (headless viewer)."),
                           SubcommandKind::Relay);
  const RelayArguments relayArguments;
  relayArguments.addTo(command);
  const QCommandLineOption pin(QStringLiteral("pin"),
                               QStringLiteral("the host certificate's SHA-256 fingerprint (default: trust the first)"),
                               QStringLiteral("fingerprint"));
  const QCommandLineOption seconds(QStringLiteral("seconds"), QStringLiteral("stop after T seconds"),
                                   QStringLiteral("T"));
  const QCommandLineOption frames(QStringLiteral("frames"), QStringLiteral("stop after N frames applied"),
                                  QStringLiteral("N"));
  const QCommandLineOption pending(QStringLiteral("pending"),
                                   QStringLiteral("frames waiting at most before older ones are dropped (default 8)"),
                                   QStringLiteral("N"), QStringLiteral("8"));
  command.parser().addOptions({pin, seconds, frames, pending});
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  auto read = relayArguments.read(command);
  if (!read) return kExitUsage;
  session::RelayViewerOptions options;
  options.nats = std::move(read->first);
  options.nats.name = QStringLiteral("shapecast viewer");
  options.sessionId = read->second;
  bool ok = true;
  options.pendingLimit = command.parser().value(pending).toInt(&ok);
  if (!ok || options.pendingLimit < 1) {
    command.error(QStringLiteral("--pending takes a positive integer"));
    return kExitUsage;
  }
  if (command.parser().isSet(pin)) {
    options.pin = session::parseFingerprint(command.parser().value(pin));
    if (!options.pin) {
      command.error(QStringLiteral("--pin takes 64 hex digits (colons allowed)"));
      return kExitUsage;
    }
  }
  const double stopAfter = command.parser().isSet(seconds) ? command.parser().value(seconds).toDouble(&ok) : 0.0;
  if (!ok || stopAfter < 0.0 || (command.parser().isSet(seconds) && stopAfter == 0.0)) {
    command.error(QStringLiteral("--seconds takes a positive number"));
    return kExitUsage;
  }
  const qint64 frameLimit = command.parser().isSet(frames) ? command.parser().value(frames).toLongLong(&ok) : 0;
  if (!ok || frameLimit < 0 || (command.parser().isSet(frames) && frameLimit == 0)) {
    command.error(QStringLiteral("--frames takes a positive integer"));
    return kExitUsage;
  }

  session::RelayViewer viewer(options);
  QString error;
  if (!viewer.start(&error)) {
    command.error(QStringLiteral("cannot watch: %1").arg(error));
    return kExitNetwork;
  }
  const bool json = command.basisArguments().json;
  QTextStream out(stdout);
  if (!json) {
    out << QStringLiteral("watching session %1: m = %2, %3 vertices, host certificate %4%5\n")
               .arg(options.sessionId)
               .arg(viewer.receiver().facts().rowCount)
               .arg(viewer.receiver().facts().vertexCount)
               .arg(session::formatFingerprint(viewer.receiver().fingerprint()),
                    options.pin ? QStringLiteral(" (pinned)") : QStringLiteral(" (trusted on first use)"));
    out.flush();
  }
  QTimer figures;
  QObject::connect(&figures, &QTimer::timeout, &viewer, [&viewer, json] {
    if (!json) QTextStream(stdout) << watchLine(watchReport(viewer)) << '\n';
  });
  figures.start(1000);
  const auto stop = [] { QCoreApplication::quit(); };
  if (frameLimit > 0) {
    QObject::connect(&viewer, &session::RelayViewer::frameApplied, &viewer, [&viewer, frameLimit] {
      if (viewer.stats().applied >= frameLimit) QCoreApplication::quit();
    });
  }
  quitOnSignal(stop);
  if (stopAfter > 0) QTimer::singleShot(static_cast<int>(stopAfter * 1000.0), &viewer, stop);
  QCoreApplication::exec();
  printReport(command, watchReport(viewer),
              [&out](const QJsonObject& r) { out << "watch ended: " << watchLine(r) << '\n'; });
  return kExitOk;
}

}  // namespace sc::app
