#include "app/cli/watch_command.h"

#include "app/cli/quit_on_signal.h"
#include "app/cli/relay_arguments.h"
#include "session/engine/distortion_probe.h"
#include "session/engine/frame_assembler.h"
#include "session/engine/relay_display.h"
#include "session/net/relay_level_fetcher.h"
#include "session/net/relay_viewer.h"
#include "session/net/tls_identity.h"
#include "session/wire/wire_format.h"
#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QCoreApplication>
#include <QJsonObject>
#include <QTextStream>
#include <QTimer>

#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

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

/// Concealment and distortion (engine/relay_display.h): frames predicted and withdrawn, exact references read,
/// and the distortion measured at the viewer's level (count 0 without --level).
void addDisplayReport(QJsonObject& report, const session::RelayViewer& viewer) {
  const session::RelayDisplay& display = viewer.display();
  const session::RelayDisplayCounts c = display.counts();
  const session::DistortionSummary& d = display.distortion();
  report.insert(QStringLiteral("concealment"), QString::fromLatin1(session::toString(display.concealment())));
  report.insert(QStringLiteral("displayed_frame"), static_cast<qint64>(display.displayedFrame()));
  report.insert(QStringLiteral("predicted"), static_cast<qint64>(c.predicted));
  report.insert(QStringLiteral("withdrawn"), static_cast<qint64>(c.withdrawn));
  report.insert(QStringLiteral("references"), static_cast<qint64>(c.references));
  report.insert(QStringLiteral("distortion_count"), static_cast<qint64>(d.count));
  report.insert(QStringLiteral("distortion_mean_pct"), d.meanPct);
  report.insert(QStringLiteral("distortion_max_pct"), d.maxPct);
  report.insert(QStringLiteral("distortion_last_pct"), d.lastPct);
}

QString displayLine(const QJsonObject& r) {
  QString line = QStringLiteral("%1: %2 frames predicted, %3 withdrawn")
                     .arg(r.value(QStringLiteral("concealment")).toString())
                     .arg(r.value(QStringLiteral("predicted")).toInteger())
                     .arg(r.value(QStringLiteral("withdrawn")).toInteger());
  const qint64 measured = r.value(QStringLiteral("distortion_count")).toInteger();
  if (measured == 0) return line + QStringLiteral("; no distortion measured yet\n");
  return line + QStringLiteral("; distortion over %1 reference frames: mean %2% max %3% last %4% of the diagonal\n")
                    .arg(measured)
                    .arg(r.value(QStringLiteral("distortion_mean_pct")).toDouble(), 0, 'f', 4)
                    .arg(r.value(QStringLiteral("distortion_max_pct")).toDouble(), 0, 'f', 4)
                    .arg(r.value(QStringLiteral("distortion_last_pct")).toDouble(), 0, 'f', 4);
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

/// The shape a viewer shows at its level: X̂' + K·Z (the CPU kernel), summarised. `checksum` is the sum of every
/// coordinate; `extent` the bounding box's sides.
struct ShownShape {
  std::uint32_t vertices = 0;
  double checksum = 0;
  Eigen::Vector3d extent = Eigen::Vector3d::Zero();
};

ShownShape shownShape(const spectral::DisplayLevel& level, const Eigen::MatrixXd& Z) {
  spectral::DisplayFrame frame;
  if (Z.rows() == level.basisSize()) frame.Z = Z.cast<float>();
  const std::vector<float> positions = spectral::reconstructed(level, frame);
  ShownShape out;
  out.vertices = level.vertexCount();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d hi = -lo;
  for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
    for (int c = 0; c < 3; ++c) {
      const double v = positions[i + static_cast<std::size_t>(c)];
      out.checksum += v;
      lo[c] = std::min(lo[c], v);
      hi[c] = std::max(hi[c], v);
    }
  }
  if (out.vertices > 0) out.extent = hi - lo;
  return out;
}

void addLevelReport(QJsonObject& report, const session::RelayLevelFetch& fetch, const session::RelayViewer& viewer) {
  report.insert(QStringLiteral("level"), fetch.index);
  if (!fetch.level) {
    report.insert(QStringLiteral("level_error"), fetch.error);
    return;
  }
  const ShownShape shape = shownShape(*fetch.level, viewer.display().display());
  report.insert(QStringLiteral("level_vertices"), static_cast<qint64>(shape.vertices));
  report.insert(QStringLiteral("level_faces"), static_cast<qint64>(fetch.entry.faceCount));
  report.insert(QStringLiteral("level_bytes"), static_cast<qint64>(fetch.entry.payloadBytes));
  report.insert(QStringLiteral("level_chunks"), static_cast<qint64>(fetch.chunks));
  report.insert(QStringLiteral("level_fetch_ms"), fetch.fetchMs);
  report.insert(QStringLiteral("level_decode_ms"), fetch.decodeMs);
  report.insert(QStringLiteral("shape_checksum"), shape.checksum);
  report.insert(QStringLiteral("shape_extent"), QStringLiteral("%1 %2 %3")
                                                    .arg(shape.extent.x(), 0, 'g', 9)
                                                    .arg(shape.extent.y(), 0, 'g', 9)
                                                    .arg(shape.extent.z(), 0, 'g', 9));
}

QString shapeLine(const QJsonObject& r) {
  if (!r.contains(QStringLiteral("level_vertices"))) return {};
  return QStringLiteral("shown: level %1, %2 vertices, checksum %3, extent %4\n")
      .arg(r.value(QStringLiteral("level")).toInteger())
      .arg(r.value(QStringLiteral("level_vertices")).toInteger())
      .arg(r.value(QStringLiteral("shape_checksum")).toDouble(), 0, 'g', 12)
      .arg(r.value(QStringLiteral("shape_extent")).toString());
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
  const QCommandLineOption level(
      QStringLiteral("level"),
      QStringLiteral("fetch level L from the session's level stream (0 = full model) and show X' + K·Z"),
      QStringLiteral("L"));
  const QCommandLineOption maxLevel(QStringLiteral("max-level-mb"),
                                    QStringLiteral("refuse a level above this many MB (default 256)"),
                                    QStringLiteral("MB"), QStringLiteral("256"));
  const QCommandLineOption concealment(
      QStringLiteral("concealment"),
      QStringLiteral(
          "what a missed frame shows: hold-last (default) or extrapolate (dead reckoning of overdue frames)"),
      QStringLiteral("mode"), QStringLiteral("hold-last"));
  command.parser().addOptions({pin, seconds, frames, pending, level, maxLevel, concealment});
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
  const std::optional<session::Concealment> mode =
      session::concealmentFromString(command.parser().value(concealment).toStdString());
  if (!mode || *mode == session::Concealment::ZeroFill) {
    command.error(QStringLiteral("--concealment takes hold-last or extrapolate"));
    return kExitUsage;
  }
  options.concealment = *mode;
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

  std::optional<std::uint8_t> levelIndex;
  if (command.parser().isSet(level)) {
    const int value = command.parser().value(level).toInt(&ok);
    if (!ok || value < 0 || value >= session::kMaxLevels) {
      command.error(QStringLiteral("--level takes an integer in [0, %1)").arg(session::kMaxLevels));
      return kExitUsage;
    }
    levelIndex = static_cast<std::uint8_t>(value);
  }
  const double maxLevelMb = command.parser().value(maxLevel).toDouble(&ok);
  if (!ok || maxLevelMb <= 0.0 || maxLevelMb > 4096.0) {
    command.error(QStringLiteral("--max-level-mb takes a number in (0, 4096]"));
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
  std::unique_ptr<session::RelayLevelFetcher> fetcher;
  if (levelIndex) {
    session::RelayLevelFetcherOptions fetchOptions;
    fetchOptions.sessionId = options.sessionId;
    fetchOptions.facts = viewer.receiver().facts();
    fetchOptions.maxLevelBytes = static_cast<std::uint64_t>(maxLevelMb * 1e6);
    fetcher = std::make_unique<session::RelayLevelFetcher>(*viewer.connection(), fetchOptions);
    if (!fetcher->start(&error)) {
      command.error(QStringLiteral("cannot fetch levels: %1").arg(error));
      return kExitNetwork;
    }
    QObject::connect(fetcher.get(), &session::RelayLevelFetcher::levelReady, &viewer, [&fetcher, &viewer, json] {
      const session::RelayLevelFetch& f = fetcher->last();
      viewer.setLevel(f.level);  // distortion is measured at the level shown
      if (json) return;
      QTextStream(stdout) << QStringLiteral(
                                 "level %1: %2 vertices, %3 faces, %4 bytes in %5 chunks from the stream (fetched in "
                                 "%6 ms, checked and decoded in %7 ms)\n")
                                 .arg(f.index)
                                 .arg(f.entry.vertexCount)
                                 .arg(f.entry.faceCount)
                                 .arg(f.entry.payloadBytes)
                                 .arg(f.chunks)
                                 .arg(f.fetchMs, 0, 'f', 1)
                                 .arg(f.decodeMs, 0, 'f', 1);
    });
    QObject::connect(fetcher.get(), &session::RelayLevelFetcher::levelRefused, &viewer,
                     [](std::uint8_t index, const QString& reason) {
                       QTextStream(stderr) << QStringLiteral("level %1 refused: %2\n").arg(index).arg(reason);
                     });
    fetcher->fetch(*levelIndex);
  }
  const auto report = [&viewer, &fetcher] {
    QJsonObject r = watchReport(viewer);
    addDisplayReport(r, viewer);
    if (fetcher && !fetcher->busy()) addLevelReport(r, fetcher->last(), viewer);
    return r;
  };
  QTimer figures;
  QObject::connect(&figures, &QTimer::timeout, &viewer, [&report, json] {
    if (json) return;
    const QJsonObject r = report();
    QTextStream(stdout) << watchLine(r) << '\n' << displayLine(r) << shapeLine(r);
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
  const QJsonObject last = report();
  printReport(command, last, [&out](const QJsonObject& r) {
    out << "watch ended: " << watchLine(r) << '\n' << displayLine(r) << shapeLine(r);
  });
  fetcher.reset();  // joins a fetch in flight
  return levelIndex && !last.contains(QStringLiteral("level_vertices")) ? kExitNetwork : kExitOk;
}

}  // namespace sc::app
