// The fan-out experiment's viewer child (`shapecast-lab fanout-viewers`, see fanout_experiment.h): K relay viewers
// sharing this process and its Qt thread, each with its own NATS connection; commands on stdin.

#include "app/cli/relay_arguments.h"
#include "experiments/fanout/fanout_experiment.h"
#include "session/engine/relay_verified_messages.h"
#include "session/net/nats_client.h"
#include "session/net/relay_viewer.h"
#include "session/net/tls_identity.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QSocketNotifier>
#include <QTextStream>
#include <QTimer>

#include <sys/resource.h>
#include <unistd.h>

#include <memory>
#include <vector>

namespace sc::app {
namespace {

double ownCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

/// A field of /proc/self/status ("Threads", "VmRSS" in kB); 0 when unreadable.
qint64 statusField(const QByteArray& name) {
  QFile file(QStringLiteral("/proc/self/status"));
  if (!file.open(QIODevice::ReadOnly)) return 0;
  const QByteArray prefix = name + ':';
  for (const QByteArray& line : file.readAll().split('\n')) {
    if (line.startsWith(prefix)) return line.mid(prefix.size()).trimmed().split(' ').front().toLongLong();
  }
  return 0;
}

void sayLine(const QString& line) {
  QTextStream out(stdout);
  out << line << '\n';
  out.flush();
}

struct Mark {
  std::int64_t applied = 0, lost = 0, dropped = 0, badSignature = 0;
};

}  // namespace

int runFanoutViewers(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("experiment fanout-viewers"),
                           QStringLiteral("The viewer child of `experiment fanout` (commands on stdin)."),
                           SubcommandKind::Relay);
  const RelayArguments relayArguments;
  relayArguments.addTo(command);
  const QCommandLineOption count(QStringLiteral("viewers"), QStringLiteral("viewers in this process"),
                                 QStringLiteral("K"), QStringLiteral("1"));
  const QCommandLineOption pin(QStringLiteral("pin"), QStringLiteral("the host certificate's fingerprint"),
                               QStringLiteral("fingerprint"));
  const QCommandLineOption pending(QStringLiteral("pending"), QStringLiteral("each viewer's pending limit"),
                                   QStringLiteral("N"), QStringLiteral("8"));
  const QCommandLineOption shared(QStringLiteral("shared-verify"),
                                  QStringLiteral("the viewers of this process verify each message once between them"));
  command.parser().addOptions({count, pin, pending, shared});
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  auto read = relayArguments.read(command);
  if (!read) return kExitUsage;
  bool ok1 = false, ok2 = false;
  const int viewers = command.parser().value(count).toInt(&ok1);
  const int pendingLimit = command.parser().value(pending).toInt(&ok2);
  const std::optional<QByteArray> fingerprint = session::parseFingerprint(command.parser().value(pin));
  if (!ok1 || !ok2 || viewers < 1 || viewers > 10000 || pendingLimit < 1 || !fingerprint) {
    command.error(QStringLiteral("--viewers takes 1..10000, --pending N ≥ 1, --pin a fingerprint"));
    return kExitUsage;
  }

  std::shared_ptr<session::RelayVerifiedMessages> verified;
  if (command.parser().isSet(shared))
    verified = std::make_shared<session::RelayVerifiedMessages>(read->second, *fingerprint);
  std::vector<std::unique_ptr<session::RelayViewer>> all;
  all.reserve(static_cast<std::size_t>(viewers));
  for (int i = 0; i < viewers; ++i) {
    session::RelayViewerOptions options;
    options.nats = read->first;
    options.nats.name = QStringLiteral("shapecast fanout viewer");
    options.sessionId = read->second;
    options.pin = fingerprint;
    options.pendingLimit = pendingLimit;
    options.sharedVerification = verified;
    auto viewer = std::make_unique<session::RelayViewer>(std::move(options));
    QString error;
    if (!viewer->start(&error)) {
      command.error(QStringLiteral("viewer %1 cannot watch: %2").arg(i).arg(error));
      return kExitNetwork;
    }
    all.push_back(std::move(viewer));
  }
  sayLine(QStringLiteral("fanout-viewers ready %1").arg(viewers));

  std::vector<Mark> marks(all.size());
  double cpuAtMark = ownCpuSeconds();
  QElapsedTimer wall;
  wall.start();
  QByteArray input;
  QSocketNotifier notifier(STDIN_FILENO, QSocketNotifier::Read);
  QObject::connect(&notifier, &QSocketNotifier::activated, &notifier, [&] {
    char buffer[256];
    const ssize_t n = ::read(STDIN_FILENO, buffer, sizeof buffer);
    if (n <= 0) {  // the parent went away
      notifier.setEnabled(false);
      QCoreApplication::exit(kExitNetwork);
      return;
    }
    input.append(buffer, static_cast<qsizetype>(n));
    for (qsizetype end = input.indexOf('\n'); end >= 0; end = input.indexOf('\n')) {
      const QByteArray word = input.left(end).trimmed();
      input.remove(0, end + 1);
      if (word == "mark") {
        for (std::size_t i = 0; i < all.size(); ++i) {
          const session::RelayViewerStats s = all[i]->stats();
          marks[i] = {s.applied, s.lost, all[i]->droppedPending(), s.badSignature};
        }
        cpuAtMark = ownCpuSeconds();
        wall.start();
        sayLine(QStringLiteral("marked"));
      } else if (word == "report") {
        QJsonArray rows;
        for (std::size_t i = 0; i < all.size(); ++i) {
          const session::RelayViewerStats s = all[i]->stats();
          rows.append(QJsonObject{
              {QStringLiteral("applied"), static_cast<qint64>(s.applied - marks[i].applied)},
              {QStringLiteral("lost"), static_cast<qint64>(s.lost - marks[i].lost)},
              {QStringLiteral("dropped_pending"), static_cast<qint64>(all[i]->droppedPending() - marks[i].dropped)},
              {QStringLiteral("bad_signature"), static_cast<qint64>(s.badSignature - marks[i].badSignature)},
              {QStringLiteral("latency_p50_ms"), s.latencyP50Ms},
              {QStringLiteral("latency_p99_ms"), s.latencyP99Ms}});
        }
        const QJsonObject report{{QStringLiteral("threads"), statusField("Threads")},
                                 {QStringLiteral("cpu_seconds"), ownCpuSeconds() - cpuAtMark},
                                 {QStringLiteral("wall_seconds"), static_cast<double>(wall.nsecsElapsed()) * 1e-9},
                                 {QStringLiteral("rss_mb"), static_cast<double>(statusField("VmRSS")) / 1024.0},
                                 {QStringLiteral("viewers"), rows}};
        sayLine(QString::fromUtf8(QJsonDocument(report).toJson(QJsonDocument::Compact)));
        QTimer::singleShot(0, QCoreApplication::instance(), &QCoreApplication::quit);
      }
    }
  });
  const int code = QCoreApplication::exec();
  all.clear();
  session::natsShutdown();
  return code;
}

}  // namespace sc::app
