#include "app/cli/host_command.h"

#include "app/cli/quit_on_signal.h"
#include "app/cli/relay_arguments.h"
#include "app/cli/session_setup.h"
#include "app/common/password_memory.h"
#include "model/decimating_level_builder.h"
#include "session/net/relay_level_publisher.h"
#include "session/net/relay_publisher.h"
#include "session/net/session_host.h"
#include "session/net/tls_identity.h"

#include <QCoreApplication>
#include <QTextStream>
#include <QTimer>

namespace sc::app {
namespace {

QString peerName(const session::PeerList& peers, session::PeerId id) {
  for (const session::PeerInfo& peer : peers.peers) {
    if (peer.peerId == id) return peer.name;
  }
  return QStringLiteral("peer %1").arg(id);
}

/// One line per peer with its latest StatsReport.
void printPeerFigures(const session::SessionHost& host) {
  QTextStream out(stdout);
  const session::PeerList peers = host.peerList();
  for (const session::PeerInfo& peer : peers.peers) {
    const std::optional<session::StatsReport> r = host.stats(peer.peerId);
    if (!r) continue;
    out << QStringLiteral(
               "  %1 (%2 vertices): %3 frames, loss %4% (last 10 s), jitter %5 ms, %6 kbit/s, "
               "latency p99 %7 ms (last 10 s), HD max %8% mean %9%\n")
               .arg(peer.name)
               .arg(r->vertexCount)
               .arg(r->framesApplied)
               .arg(100.0 * r->lossFraction, 0, 'f', 1)
               .arg(r->jitterMs, 0, 'f', 2)
               .arg(r->payloadKbpsIn, 0, 'f', 1)
               .arg(r->latencyP99Ms, 0, 'f', 2)
               .arg(r->hdMaxPct, 0, 'f', 3)
               .arg(r->hdMeanPct, 0, 'f', 4);
  }
  out.flush();
}

/// One line for the relay's viewers, aggregated.
void printAudience(const session::RelayPublisher& publisher) {
  const session::RelayAudienceSummary a = publisher.audience();
  QTextStream(stdout) << QStringLiteral(
                             "  relay: %1 frames published; %2 viewers reporting: loss median %3% max %4%, latency "
                             "p99 median %5 ms max %6 ms, %7 forged frames dropped\n")
                             .arg(publisher.counters().frames)
                             .arg(a.viewers)
                             .arg(100.0 * a.lossFraction.median, 0, 'f', 2)
                             .arg(100.0 * a.lossFraction.max, 0, 'f', 2)
                             .arg(a.latencyP99Ms.median, 0, 'f', 2)
                             .arg(a.latencyP99Ms.max, 0, 'f', 2)
                             .arg(a.badSignature);
  if (a.distortionViewers > 0) {
    QTextStream(stdout) << QStringLiteral(
                               "  relay distortion: %1 viewers measuring, mean median %2% max %3%, largest "
                               "%4%; %5 frames predicted\n")
                               .arg(a.distortionViewers)
                               .arg(a.distortionMeanPct.median, 0, 'f', 4)
                               .arg(a.distortionMeanPct.max, 0, 'f', 4)
                               .arg(a.distortionMaxPct.max, 0, 'f', 4)
                               .arg(a.concealed);
  }
}

}  // namespace

int runHostCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("host"), QStringLiteral("Host a ShapeCast session for MESH."));
  const QCommandLineOption port(QStringLiteral("port"), QStringLiteral("TCP port (default 47100; 0 = any)"),
                                QStringLiteral("port"), QStringLiteral("47100"));
  const QCommandLineOption udpPort(QStringLiteral("udp-port"), QStringLiteral("UDP port (default: any)"),
                                   QStringLiteral("port"), QStringLiteral("0"));
  const QCommandLineOption passwordFile(QStringLiteral("password-file"),
                                        QStringLiteral("session password: the first line of this file"),
                                        QStringLiteral("file"));
  const QCommandLineOption name(QStringLiteral("name"), QStringLiteral("the host's display name"),
                                QStringLiteral("name"), QStringLiteral("host"));
  const QCommandLineOption mode(QStringLiteral("mode"), QStringLiteral("deformation mode: linear or rigid"),
                                QStringLiteral("mode"), QStringLiteral("linear"));
  const QCommandLineOption referenceEvery(QStringLiteral("reference-every"),
                                          QStringLiteral("exact reference frame every N frames (default 15)"),
                                          QStringLiteral("N"), QStringLiteral("15"));
  const QCommandLineOption seconds(QStringLiteral("seconds"), QStringLiteral("stop after T seconds (default: Ctrl-C)"),
                                   QStringLiteral("T"));
  const QCommandLineOption editors(QStringLiteral("editors"),
                                   QStringLiteral("people who may drag at once, each their own handle (default 4)"),
                                   QStringLiteral("N"), QStringLiteral("4"));
  command.parser().addOptions({port, udpPort, passwordFile, name, mode, referenceEvery, seconds, editors});
  const RelayArguments relayArguments;
  relayArguments.addTo(command);
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  std::optional<session::RelayPublisherOptions> relay;
  if (!relayArguments.readPublisher(command, QStringLiteral("shapecast host"), relay)) return kExitUsage;

  session::SessionHostOptions options;
  options.levelBuilder = session::LevelBuilder{model::levelTargetList, model::decimatedLevel};
  bool ok = false, ok2 = false, ok3 = false;
  options.tcpPort = static_cast<quint16>(command.parser().value(port).toUInt(&ok));
  options.udpPort = static_cast<quint16>(command.parser().value(udpPort).toUInt(&ok2));
  options.referenceEvery = command.parser().value(referenceEvery).toInt(&ok3);
  if (!ok || !ok2 || !ok3 || options.referenceEvery < 0) {
    command.error(QStringLiteral("--port, --udp-port and --reference-every take non-negative integers"));
    return kExitUsage;
  }
  options.maxEditors = command.parser().value(editors).toInt(&ok);
  if (!ok || options.maxEditors < 1 || options.maxEditors > session::kMaxPeers) {
    command.error(QStringLiteral("--editors takes a number of people from 1 to %1").arg(session::kMaxPeers));
    return kExitUsage;
  }
  const QString modeName = command.parser().value(mode);
  if (modeName != QLatin1String("linear") && modeName != QLatin1String("rigid")) {
    command.error(QStringLiteral("--mode must be linear or rigid, not '%1'").arg(modeName));
    return kExitUsage;
  }
  options.deformer.mode =
      modeName == QLatin1String("rigid") ? spectral::DeformationMode::Rigid : spectral::DeformationMode::Linear;
  options.hostName = command.parser().value(name);
  if (command.parser().isSet(passwordFile)) {
    options.password = readPasswordFile(command, command.parser().value(passwordFile));
    if (!options.password) return kExitUsage;
  }
  std::optional<double> stopAfter;
  if (command.parser().isSet(seconds)) {
    stopAfter = command.parser().value(seconds).toDouble(&ok);
    if (!ok || *stopAfter <= 0.0) {
      command.error(QStringLiteral("--seconds takes a positive number"));
      return kExitUsage;
    }
  }

  const std::shared_ptr<const session::HostModel> model = loadHostModel(command, command.meshPath(), exitCode);
  if (!model) return exitCode;

  session::SessionHost host(model, options);
  QString error;
  const bool started = host.start(&error);  // derives the password's key
  const bool passwordRequired = options.password.has_value();
  forgetPassword(options.password);
  if (!started) {
    command.error(QStringLiteral("cannot host: %1").arg(error));
    return kExitNetwork;
  }
  QTextStream out(stdout);
  out << QStringLiteral("hosting %1: %2 vertices, m = %3, %4 mode, TCP port %5, UDP port %6%7\n")
             .arg(command.meshPath())
             .arg(model->vertexCount())
             .arg(model->rowCount())
             .arg(modeName)
             .arg(host.tcpPort())
             .arg(host.udpPort())
             .arg(passwordRequired ? QStringLiteral(", password required") : QString());
  const QString fingerprint = session::formatFingerprint(host.fingerprint());
  out << QStringLiteral("TLS certificate fingerprint (SHA-256), for joiners to compare: %1\n").arg(fingerprint);
  out << QStringLiteral("join with: shapecast-cli join 127.0.0.1:%1 --name NAME --fingerprint %2\n")
             .arg(host.tcpPort())
             .arg(fingerprint);
  std::unique_ptr<session::RelayPublisher> publisher;
  std::unique_ptr<session::RelayLevelPublisher> levelPublisher;
  if (relay) {
    const QString sessionId = relay->sessionId;
    const QString url = relay->nats.url;
    publisher = std::make_unique<session::RelayPublisher>(host, std::move(*relay));
    if (!publisher->start(&error)) {
      command.error(QStringLiteral("cannot publish to the relay: %1").arg(error));
      return kExitNetwork;
    }
    // Every level payload once, on the session's level stream (viewers' `watch --level`).
    levelPublisher = std::make_unique<session::RelayLevelPublisher>(host, *publisher->connection(),
                                                                    session::RelayLevelPublisherOptions{sessionId});
    if (!levelPublisher->start(&error)) {
      command.error(QStringLiteral("cannot publish the levels to the relay: %1").arg(error));
      return kExitNetwork;
    }
    QObject::connect(levelPublisher.get(), &session::RelayLevelPublisher::levelPublished, &host,
                     [&levelPublisher](std::uint8_t index) {
                       const session::RelayLevelEntry* entry = levelPublisher->list().find(index);
                       QTextStream(stdout) << QStringLiteral("relay: level %1 published (%2 vertices, %3 bytes)\n")
                                                  .arg(index)
                                                  .arg(entry ? entry->vertexCount : 0)
                                                  .arg(entry ? entry->payloadBytes : 0);
                     });
    QObject::connect(levelPublisher.get(), &session::RelayLevelPublisher::levelFailed, &host,
                     [](std::uint8_t index, const QString& reason) {
                       QTextStream(stdout)
                           << QStringLiteral("relay: level %1 not published: %2\n").arg(index).arg(reason);
                     });
    out << QStringLiteral(
               "relaying session %1 through %2; watch with: shapecast-cli watch --nats %2 --session %1 "
               "--nats-user USER --nats-password-file FILE --pin %3\n")
               .arg(sessionId, url, fingerprint);
  }
  out.flush();

  QObject::connect(&host, &session::SessionHost::logMessage, &host,
                   [](const QString& message) { QTextStream(stdout) << message << '\n'; });
  QObject::connect(&host, &session::SessionHost::lockChanged, &host, [&host] {
    QStringList holders;
    for (const session::LockHolding& lease : host.lockHolders()) {
      holders << QStringLiteral("%1 (epoch %2)").arg(peerName(host.peerList(), lease.peer)).arg(lease.epoch);
    }
    QTextStream(stdout) << (holders.isEmpty()
                                ? QStringLiteral("lock: free\n")
                                : QStringLiteral("lock: held by %1\n").arg(holders.join(QStringLiteral(", "))));
  });
  QTimer figures;
  QObject::connect(&figures, &QTimer::timeout, &host, [&host, &publisher] {
    printPeerFigures(host);
    if (publisher) printAudience(*publisher);
  });
  figures.start(5000);

  const auto stop = [&host] {
    host.shutdown();
    QTimer::singleShot(200, QCoreApplication::instance(), &QCoreApplication::quit);  // let the Leaves go out
  };
  quitOnSignal(stop);
  if (stopAfter) QTimer::singleShot(static_cast<int>(*stopAfter * 1000.0), &host, stop);
  QCoreApplication::exec();
  if (publisher) {
    out << QStringLiteral("relay: %1 frames, %2 keyframes, %3 bytes published\n")
               .arg(publisher->counters().frames)
               .arg(publisher->counters().keyframes)
               .arg(publisher->counters().bytes);
    out << QStringLiteral("relay: %1 levels, %2 chunks, %3 level bytes published\n")
               .arg(levelPublisher->counters().levels)
               .arg(levelPublisher->counters().chunks)
               .arg(levelPublisher->counters().bytes);
  }
  levelPublisher.reset();
  publisher.reset();
  out << "host stopped\n";
  return kExitOk;
}

}  // namespace sc::app
