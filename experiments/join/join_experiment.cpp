// The join experiment's run (see join_experiment.h): the host child, one rate-limited client, the times.

#include "experiments/join/join_experiment.h"

#include "app/cli/session_setup.h"
#include "experiments/load/host_child.h"
#include "session/engine/session_clock.h"
#include "session/net/session_client.h"

#include <sys/resource.h>

#include <optional>

namespace sc::app {
namespace {

/// Peak resident set size of this process so far, MiB (getrusage ru_maxrss; Linux reports KiB).
double peakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

double secondsSince(session::Micros start) {
  return 1e-6 * static_cast<double>((session::sessionNow() - start).count());
}

/// What the client's signals marked, in seconds since start.
struct JoinMarks {
  std::optional<double> transferStart, firstProgress, transferDone, firstLevel, levelReady, firstFrame;
  std::uint32_t firstLevelVertices = 0;
  quint64 transferBytes = 0;
};

}  // namespace

std::variant<JoinResult, QString> runJoinExperiment(const QString& executable, const QString& meshPath,
                                                    const QStringList& basisArguments,
                                                    const JoinExperimentSettings& settings,
                                                    const std::function<void(const QString&)>& progress) {
  const auto say = [&progress](const QString& line) {
    if (progress) progress(line);
  };
  JoinResult result;
  result.mesh = meshPath;
  result.settings = settings;
  say(QStringLiteral("starting the host process (basis of %1)").arg(meshPath));
  HostChild host;
  if (!host.start(executable, QStringList{QStringLiteral("experiment"), QStringLiteral("load-host"), meshPath,
                                          QStringLiteral("--clients"), QStringLiteral("1")} +
                                  basisArguments)) {
    return QStringLiteral("cannot start the host process");
  }
  const QStringList hello =
      host.waitLine(QStringLiteral("load-host port"), std::chrono::minutes(30)).split(QLatin1Char(' '));
  if (hello.size() != 7) return QStringLiteral("the host process did not start hosting");
  result.vertices = hello[4].toInt();
  result.rows = hello[6].toInt();
  host.command(QByteArrayLiteral("drag 100000"));  // loops the drag until the report
  // The load-host's scripted drag is refused on some meshes (the 100k dragon): then only the level is timed.
  result.hostDrags = host.waitLine(QStringLiteral("drag failed"), std::chrono::seconds(3)).isEmpty();
  if (!result.hostDrags) say(QStringLiteral("the host cannot play its drag on this mesh: timing the level only"));

  session::SessionClientOptions options;
  options.port = static_cast<quint16>(hello[2].toUInt());
  options.name = QStringLiteral("join experiment");
  options.level = settings.level;
  options.progressive = settings.progressive;
  session::ImpairmentSettings impairment;
  impairment.loss = settings.loss;
  impairment.delay = std::chrono::milliseconds(settings.delayMs);
  impairment.rate.bitsPerSecond = settings.rateMbit * 1e6;
  if (!impairment.isIdeal()) options.impairment = impairment;
  result.baselineRssMb = peakResidentMegabytes();

  session::SessionClient client(options);
  JoinMarks marks;
  const session::Micros start = session::sessionNow();
  // Each transfer starts with a progress of 0 (its ModelBegin) and ends at received == total: the last one is the
  // requested level's.
  QObject::connect(&client, &session::SessionClient::modelProgress, &client, [&](quint64 received, quint64 total) {
    if (received == 0) marks.transferStart = secondsSince(start);
    if (received == total && marks.transferStart) {
      marks.firstProgress = marks.transferStart;
      marks.transferDone = secondsSince(start);
      marks.transferBytes = total;
    }
  });
  QObject::connect(&client, &session::SessionClient::levelReady, &client, [&](std::uint32_t vertices) {
    if (!marks.firstLevel) {
      marks.firstLevel = secondsSince(start);
      marks.firstLevelVertices = vertices;
    }
    if (!client.levelPending()) marks.levelReady = secondsSince(start);
  });
  QObject::connect(&client, &session::SessionClient::frameUpdated, &client, [&] {
    if (marks.firstLevel && !marks.firstFrame && client.channel().hasFrame()) marks.firstFrame = secondsSince(start);
  });
  say(QStringLiteral("joining over %1 Mbit/s, %2 ms, %3 loss")
          .arg(settings.rateMbit)
          .arg(settings.delayMs)
          .arg(settings.loss));
  client.start();
  const bool joined = waitUntil(
      [&] {
        const auto state = client.state();
        return (marks.levelReady.has_value() && (marks.firstFrame.has_value() || !result.hostDrags)) ||
               state == session::SessionClient::State::Failed || state == session::SessionClient::State::Left;
      },
      std::chrono::milliseconds(static_cast<std::int64_t>(settings.timeoutSeconds * 1000.0)));
  result.peakRssMb = peakResidentMegabytes();
  result.streamBytes = client.streamBytesRead();
  result.datagramBytes = client.channel().bytesRead();
  result.levelVertices = client.levelVertexCount();
  QString error = client.errorText();
  if (error.isEmpty()) {
    error =
        QStringLiteral("timeout (level %1 vertices%2, %3 frames applied)")
            .arg(client.levelVertexCount())
            .arg(client.levelError().isEmpty() ? QString() : QStringLiteral(", level error: ") + client.levelError())
            .arg(client.channel().framesApplied());
  }
  client.leave();
  host.command(QByteArrayLiteral("report"));
  host.waitLine(QStringLiteral("{"), std::chrono::seconds(30));
  if (!joined || !marks.levelReady || (result.hostDrags && !marks.firstFrame)) {
    return QStringLiteral("the client did not show a frame: %1").arg(error);
  }
  result.levelReadySeconds = *marks.levelReady;
  result.firstFrameSeconds = marks.firstFrame.value_or(-1.0);
  result.firstLevelSeconds = marks.firstLevel.value_or(-1.0);
  result.firstLevelVertices = marks.firstLevelVertices;
  if (marks.firstProgress && marks.transferDone && *marks.transferDone > *marks.firstProgress) {
    result.transferMbit =
        static_cast<double>(marks.transferBytes) * 8e-6 / (*marks.transferDone - *marks.firstProgress);
  }
  say(QStringLiteral("done"));
  return result;
}

QJsonObject joinResultJson(const JoinResult& r) {
  return {{QStringLiteral("mesh"), r.mesh},
          {QStringLiteral("vertices"), r.vertices},
          {QStringLiteral("rows"), r.rows},
          {QStringLiteral("level_vertices"), static_cast<qint64>(r.levelVertices)},
          {QStringLiteral("rate_mbit"), r.settings.rateMbit},
          {QStringLiteral("delay_ms"), r.settings.delayMs},
          {QStringLiteral("loss"), r.settings.loss},
          {QStringLiteral("bytes_received"), static_cast<qint64>(r.streamBytes + r.datagramBytes)},
          {QStringLiteral("stream_bytes"), static_cast<qint64>(r.streamBytes)},
          {QStringLiteral("datagram_bytes"), static_cast<qint64>(r.datagramBytes)},
          {QStringLiteral("first_frame_s"), r.hostDrags ? QJsonValue(r.firstFrameSeconds) : QJsonValue()},
          {QStringLiteral("host_drags"), r.hostDrags},
          {QStringLiteral("level_ready_s"), r.levelReadySeconds},
          {QStringLiteral("first_level_s"), r.firstLevelSeconds},
          {QStringLiteral("first_level_vertices"), static_cast<qint64>(r.firstLevelVertices)},
          {QStringLiteral("progressive"), r.settings.progressive},
          {QStringLiteral("transfer_mbit"), r.transferMbit},
          {QStringLiteral("peak_rss_mb"), r.peakRssMb},
          {QStringLiteral("baseline_rss_mb"), r.baselineRssMb}};
}

}  // namespace sc::app
