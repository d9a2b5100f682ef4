#include "app/cli/join_command.h"

#include "app/cli/peak_memory.h"
#include "app/cli/peer_arguments.h"
#include "app/cli/quit_on_signal.h"
#include "app/cli/session_setup.h"
#include "app/common/password_memory.h"
#include "session/engine/session_clock.h"
#include "session/net/distortion_meter.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QMetaEnum>
#include <QTextStream>
#include <QTimer>

namespace sc::app {
namespace {

struct JoinArguments {
  session::SessionClientOptions client;
  std::optional<double> seconds;
  QString statsJson;
};

std::optional<JoinArguments> parseJoinArguments(SubcommandParser& command, const QStringList& arguments,
                                                int& exitCode) {
  QCommandLineParser& p = command.parser();
  const PeerArguments peer(command, QStringLiteral("client"));
  const QCommandLineOption level(QStringLiteral("level"),
                                 QStringLiteral("display resolution: full, or the level closest to N vertices"),
                                 QStringLiteral("full|N"), QStringLiteral("full"));
  const QCommandLineOption loss(QStringLiteral("loss"), QStringLiteral("simulated datagram loss ratio, 0..1"),
                                QStringLiteral("P"), QStringLiteral("0"));
  const QCommandLineOption burst(QStringLiteral("burst"),
                                 QStringLiteral("Gilbert-Elliott loss with mean burst length L (datagrams)"),
                                 QStringLiteral("L"));
  const QCommandLineOption delay(QStringLiteral("delay-ms"),
                                 QStringLiteral("simulated one-way delay added to every datagram received, ms"),
                                 QStringLiteral("D"), QStringLiteral("0"));
  const QCommandLineOption rate(QStringLiteral("rate-mbit"),
                                QStringLiteral("simulated link rate in Mbit/s for everything received (the model "
                                               "transfer and the datagrams share it); 0 = unlimited"),
                                QStringLiteral("R"), QStringLiteral("0"));
  const QCommandLineOption seed(QStringLiteral("seed"), QStringLiteral("seed of the simulated loss (default 1)"),
                                QStringLiteral("S"), QStringLiteral("1"));
  const QCommandLineOption zeroFill(QStringLiteral("zero-fill"),
                                    QStringLiteral("conceal lost bands with zeros (the paper's way); same as "
                                                   "--concealment zero-fill"));
  const QCommandLineOption concealment(
      QStringLiteral("concealment"),
      QStringLiteral("what lost datagrams show: hold-last, zero-fill, or extrapolate (hold-last + dead reckoning "
                     "of missing rows and overdue frames); default %1")
          .arg(QString::fromLatin1(session::toString(session::SessionClientOptions{}.concealment))),
      QStringLiteral("name"));
  const QCommandLineOption seconds(QStringLiteral("seconds"), QStringLiteral("leave after T seconds"),
                                   QStringLiteral("T"));
  const QCommandLineOption statsJson(QStringLiteral("stats-json"), QStringLiteral("write the final figures here"),
                                     QStringLiteral("file"));
  const QCommandLineOption direct(QStringLiteral("no-progressive"),
                                  QStringLiteral("download the requested level only (by default the host's smallest "
                                                 "level comes first and shows the live shape meanwhile)"));
  p.addOptions({level, loss, burst, delay, rate, seed, zeroFill, concealment, seconds, statsJson, direct});
  if (!command.parse(arguments, exitCode)) return std::nullopt;
  exitCode = kExitUsage;

  JoinArguments args;
  if (!peer.apply(command, args.client)) return std::nullopt;
  bool ok = true;
  if (p.value(level) != QLatin1String("full")) {
    const uint vertices = p.value(level).toUInt(&ok);
    if (!ok || vertices == 0) {
      command.error(QStringLiteral("--level takes 'full' or a positive vertex count"));
      return std::nullopt;
    }
    args.client.level = vertices;
  }
  const double lossRatio = p.value(loss).toDouble(&ok);
  if (!ok || lossRatio < 0.0 || lossRatio > 1.0) {
    command.error(QStringLiteral("--loss takes a ratio between 0 and 1"));
    return std::nullopt;
  }
  const qulonglong seedValue = p.value(seed).toULongLong(&ok);
  if (!ok) {
    command.error(QStringLiteral("--seed takes a non-negative integer"));
    return std::nullopt;
  }
  const int delayMs = p.value(delay).toInt(&ok);
  if (!ok || delayMs < 0) {
    command.error(QStringLiteral("--delay-ms takes a non-negative whole number of milliseconds"));
    return std::nullopt;
  }
  const double rateMbit = p.value(rate).toDouble(&ok);
  if (!ok || !(rateMbit >= 0.0) || rateMbit > 100000.0) {
    command.error(QStringLiteral("--rate-mbit takes a rate in Mbit/s between 0 (unlimited) and 100000"));
    return std::nullopt;
  }
  if (lossRatio > 0.0 || p.isSet(burst) || delayMs > 0 || rateMbit > 0.0) {
    session::ImpairmentSettings impairment;
    impairment.loss = lossRatio;
    impairment.seed = seedValue;
    impairment.delay = std::chrono::milliseconds(delayMs);
    impairment.rate.bitsPerSecond = rateMbit * 1e6;
    if (p.isSet(burst)) {
      impairment.burst = true;
      impairment.burstLength = p.value(burst).toDouble(&ok);
      if (!ok || impairment.burstLength < 1.0) {
        command.error(QStringLiteral("--burst takes a mean burst length ≥ 1"));
        return std::nullopt;
      }
    }
    args.client.impairment = impairment;
  }
  if (p.isSet(zeroFill)) args.client.concealment = session::Concealment::ZeroFill;
  if (p.isSet(concealment)) {
    const std::optional<session::Concealment> c = session::concealmentFromString(p.value(concealment).toStdString());
    if (!c || (p.isSet(zeroFill) && *c != session::Concealment::ZeroFill)) {
      command.error(
          QStringLiteral("--concealment takes hold-last, zero-fill or extrapolate (and agrees with "
                         "--zero-fill)"));
      return std::nullopt;
    }
    args.client.concealment = *c;
  }
  if (p.isSet(seconds)) {
    args.seconds = p.value(seconds).toDouble(&ok);
    if (!ok || *args.seconds <= 0.0) {
      command.error(QStringLiteral("--seconds takes a positive number"));
      return std::nullopt;
    }
  }
  args.statsJson = p.value(statsJson);
  args.client.progressive = !p.isSet(direct);
  exitCode = kExitOk;
  return args;
}

/// When the first level became ready: seconds from client.start(), and the stream bytes read by then.
struct JoinTiming {
  double levelReadySeconds = 0.0;
  std::uint64_t levelReadyBytes = 0;
};

QJsonObject figures(session::SessionClient& client, const session::DistortionMeter& meter, const JoinTiming& timing) {
  const session::ReceiverReport r = client.channel().peek(session::sessionNow());
  const session::DistortionSummary& hd = meter.summary();
  return {{QStringLiteral("level_ready_s"), timing.levelReadySeconds},
          {QStringLiteral("level_ready_stream_bytes"), static_cast<qint64>(timing.levelReadyBytes)},
          {QStringLiteral("stream_bytes"), static_cast<qint64>(client.streamBytesRead())},
          {QStringLiteral("peak_rss_mb"), peakResidentMegabytes()},
          {QStringLiteral("state"), QString::fromLatin1(QMetaEnum::fromType<session::SessionClient::State>().valueToKey(
                                        static_cast<int>(client.state())))},
          {QStringLiteral("level_vertices"), static_cast<qint64>(client.levelVertexCount())},
          {QStringLiteral("frames_applied"), static_cast<qint64>(client.channel().framesApplied())},
          {QStringLiteral("datagrams_received"), static_cast<qint64>(r.received)},
          {QStringLiteral("datagrams_lost"), static_cast<qint64>(r.cumulativeLost)},
          {QStringLiteral("datagrams_late"), static_cast<qint64>(r.late)},
          {QStringLiteral("datagrams_dropped"), static_cast<qint64>(client.channel().droppedDatagrams())},
          {QStringLiteral("loss_fraction"), r.lossFraction},
          {QStringLiteral("jitter_ms"), r.jitterMs},
          {QStringLiteral("kbps_in"), r.payloadKbps},
          {QStringLiteral("wire_kbps_in"), r.wireKbps},
          {QStringLiteral("fps"), r.framesPerSecond},
          {QStringLiteral("latency_p50_ms"), r.latencyP50Ms},
          {QStringLiteral("latency_p99_ms"), r.latencyP99Ms},
          // The last 10 s (issue 16): what the desktop's docks show for the same session.
          {QStringLiteral("loss_fraction_recent"), r.recentLossFraction},
          {QStringLiteral("latency_p50_recent_ms"), r.recentLatencyP50Ms},
          {QStringLiteral("latency_p99_recent_ms"), r.recentLatencyP99Ms},
          {QStringLiteral("hd_max_pct"), hd.maxPct},
          {QStringLiteral("hd_mean_pct"), hd.meanPct},
          {QStringLiteral("hd_last_pct"), hd.lastPct},
          {QStringLiteral("hd_samples"), static_cast<qint64>(hd.count)},
          {QStringLiteral("keyframes"), static_cast<qint64>(client.keyframesReceived())}};
}

/// One line of figures, on `stream` (stdout, or stderr when stdout is reserved for --json).
void printLine(const QJsonObject& f, FILE* stream = stdout) {
  QTextStream(stream)
      << QStringLiteral(
             "%1 frames | loss %2% (last 10 s %8%) | %3 kbit/s | %4 fps | latency p99 %5 ms (last 10 s %9 ms) | "
             "HD last %6% max %7%\n")
             .arg(f[QStringLiteral("frames_applied")].toInteger())
             .arg(100.0 * f[QStringLiteral("loss_fraction")].toDouble(), 0, 'f', 1)
             .arg(f[QStringLiteral("kbps_in")].toDouble(), 0, 'f', 1)
             .arg(f[QStringLiteral("fps")].toDouble(), 0, 'f', 0)
             .arg(f[QStringLiteral("latency_p99_ms")].toDouble(), 0, 'f', 2)
             .arg(f[QStringLiteral("hd_last_pct")].toDouble(), 0, 'f', 4)
             .arg(f[QStringLiteral("hd_max_pct")].toDouble(), 0, 'f', 4)
             .arg(100.0 * f[QStringLiteral("loss_fraction_recent")].toDouble(), 0, 'f', 1)
             .arg(f[QStringLiteral("latency_p99_recent_ms")].toDouble(), 0, 'f', 2);
}

}  // namespace

int runJoinCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("join"), QStringLiteral("Join a ShapeCast session headless."),
                           SubcommandKind::Peer);
  int exitCode = kExitOk;
  std::optional<JoinArguments> args = parseJoinArguments(command, arguments, exitCode);
  if (!args) return exitCode;

  session::SessionClient client(args->client);
  forgetPassword(args->client.password);  // the client keeps its own copy until its proof
  session::DistortionMeter meter(client, session::DistortionMeter::Mode::Live, &client);
  // --level N: the host serves the rung closest to N (by exact counts where built); once the host's level list is
  // complete, ask for the closest exact level should that be another one (at most once).
  FILE* progress = command.basisArguments().json ? stderr : stdout;
  bool exactRequested = false;
  QObject::connect(&client, &session::SessionClient::levelsChanged, &client, [&, progress] {
    if (exactRequested || !client.levels().complete()) return;
    exactRequested = true;
    QStringList counts;
    for (const session::LevelInfo& level : client.levels().levels) counts << QString::number(level.vertexCount);
    QTextStream(progress) << QStringLiteral("host levels (vertices): %1\n").arg(counts.join(QStringLiteral(", ")));
    const session::LevelInfo* closest = session::closestLevel(client.levels(), args->client.level);
    if (args->client.level == 0 || closest == nullptr || closest->vertexCount == client.levelVertexCount()) return;
    QTextStream(progress)
        << QStringLiteral("asking for the closest exact level: %1 vertices\n").arg(closest->vertexCount);
    client.requestResolution(closest->vertexCount);
  });
  // Each level as it arrives (a progressive join shows the host's smallest level first, then the requested one).
  const session::Micros joinStart = session::sessionNow();
  QObject::connect(&client, &session::SessionClient::levelReady, &client, [&, progress](std::uint32_t vertices) {
    QTextStream(progress) << QStringLiteral("level of %1 vertices shown after %2 s%3\n")
                                 .arg(vertices)
                                 .arg(1e-6 * static_cast<double>((session::sessionNow() - joinStart).count()), 0, 'f',
                                      2)
                                 .arg(client.levelPending() ? QStringLiteral(" (preview; the requested level follows)")
                                                            : QString());
  });
  // Under an emulated link rate a large level takes as long as it takes (46 MB at 1 Mbit/s: 6 minutes).
  const bool rated = args->client.impairment && args->client.impairment->rate.bitsPerSecond > 0.0;
  QElapsedTimer sinceStart;
  sinceStart.start();
  const std::chrono::milliseconds levelWait = rated ? std::chrono::seconds(3600) : std::chrono::seconds(120);
  if (!joinAndWait(command, client, levelWait)) return kExitNetwork;
  // A progressive join is Ready on the host's smallest level; the figures below are those of the requested one.
  if (client.levelPending()) {
    const session::Welcome& welcome = *client.session();
    const bool arrived = waitUntil(
        [&client] { return !client.levelPending() || client.state() != session::SessionClient::State::Ready; },
        levelWaitTimeout(welcome.vertexCount, welcome.rowCount, levelWait));
    if (!arrived || client.state() != session::SessionClient::State::Ready) {
      command.error(QStringLiteral("the requested level did not arrive: %1").arg(client.errorText()));
      return kExitNetwork;
    }
  }
  const JoinTiming timing{static_cast<double>(sinceStart.nsecsElapsed()) / 1e9, client.streamBytesRead()};
  QTextStream(progress) << QStringLiteral(
                               "joined as peer %1, displaying %2 vertices: level ready in %3 s, %4 bytes "
                               "read, peak RSS %5 MB\n")
                               .arg(client.peerId())
                               .arg(client.levelVertexCount())
                               .arg(timing.levelReadySeconds, 0, 'f', 2)
                               .arg(timing.levelReadyBytes)
                               .arg(peakResidentMegabytes(), 0, 'f', 0);

  QTimer ticker;
  QObject::connect(&ticker, &QTimer::timeout, &client, [&] { printLine(figures(client, meter, timing), progress); });
  ticker.start(1000);
  const auto stop = [&client] {
    client.leave();
    QTimer::singleShot(100, QCoreApplication::instance(), &QCoreApplication::quit);
  };
  QObject::connect(&client, &session::SessionClient::stateChanged, &client, [](session::SessionClient::State s) {
    if (s == session::SessionClient::State::Left || s == session::SessionClient::State::Failed)
      QCoreApplication::quit();
  });
  quitOnSignal(stop);
  if (args->seconds) QTimer::singleShot(static_cast<int>(*args->seconds * 1000.0), &client, stop);
  QCoreApplication::exec();

  const QJsonObject final = figures(client, meter, timing);
  if (client.leaveReason()) {  // the host ended the session or removed us: no error, but say so
    QTextStream(progress) << QStringLiteral("session ended: %1\n").arg(client.errorText());
  }
  if (client.state() == session::SessionClient::State::Failed) {
    command.error(QStringLiteral("session ended: %1").arg(client.errorText()));
    exitCode = kExitNetwork;
  }
  if (!args->statsJson.isEmpty()) {
    QFile file(args->statsJson);
    if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate) || file.write(QJsonDocument(final).toJson()) < 0) {
      command.error(QStringLiteral("cannot write '%1': %2").arg(args->statsJson, file.errorString()));
      return kExitUsage;
    }
  }
  printReport(command, final, [](const QJsonObject& f) { printLine(f); });
  return exitCode;
}

}  // namespace sc::app
