// The fan-out experiment's run (see fanout_experiment.h): a local nats-server, the relaying host child, the viewer
// children, and the figures they report.

#include "experiments/fanout/fanout_experiment.h"

#include "experiments/load/host_child.h"
#include "session/net/local_nats_server.h"

#include <QElapsedTimer>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QTemporaryDir>
#include <QThread>

#include <unistd.h>

#include <algorithm>
#include <memory>

namespace sc::app {
namespace {

const QString kSession = QStringLiteral("fanout");
// The children run under a QGuiApplication, which takes "-session ID" / "--session ID" (X11 session management)
// before any parser of ours sees it: they get "--session=ID".

/// utime + stime of process `pid` in seconds (/proc/<pid>/stat fields 14 and 15); 0 when unreadable.
double childCpuSeconds(qint64 pid) {
  QFile file(QStringLiteral("/proc/%1/stat").arg(pid));
  if (!file.open(QIODevice::ReadOnly)) return 0.0;
  const QByteArray text = file.readAll();
  const qsizetype close = text.lastIndexOf(')');  // the command name may hold spaces
  if (close < 0) return 0.0;
  const QList<QByteArray> fields = text.mid(close + 2).split(' ');  // fields[0] is field 3 (state)
  if (fields.size() < 13) return 0.0;
  const double ticks = static_cast<double>(sysconf(_SC_CLK_TCK));
  return (fields[11].toDouble() + fields[12].toDouble()) / ticks;
}

double loadAverageNow() {
  QFile file(QStringLiteral("/proc/loadavg"));
  return file.open(QIODevice::ReadOnly) ? file.readAll().split(' ').front().toDouble() : 0.0;
}

bool writeSecret(const QString& path, const QString& secret) {
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly) || !file.setPermissions(QFileDevice::ReadOwner | QFileDevice::WriteOwner))
    return false;
  return file.write(secret.toUtf8() + '\n') > 0;
}

double middleValue(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

std::variant<FanoutResult, QString> runFanoutExperiment(const QString& executable, const QString& meshPath,
                                                        const QStringList& basisArguments,
                                                        const FanoutExperimentSettings& settings,
                                                        const std::function<void(const QString&)>& progress) {
  const auto say = [&progress](const QString& line) {
    if (progress) progress(line);
  };
  FanoutResult result;
  result.mesh = meshPath;
  result.settings = settings;

  session::NatsServerConfig config;
  config.sessionId = kSession;
  session::LocalNatsServer server(config);
  QString error;
  if (!server.start(&error)) return QStringLiteral("cannot start nats-server: %1").arg(error);
  QTemporaryDir secrets;
  const QString hostSecret = secrets.filePath(QStringLiteral("host.pw"));
  const QString viewerSecret = secrets.filePath(QStringLiteral("viewer.pw"));
  if (!secrets.isValid() || !writeSecret(hostSecret, config.hostPassword) ||
      !writeSecret(viewerSecret, config.viewerPassword)) {
    return QStringLiteral("cannot write the NATS password files");
  }
  say(QStringLiteral("nats-server %1 on %2").arg(server.pid()).arg(server.url()));

  say(QStringLiteral("starting the host process (basis of %1)").arg(meshPath));
  HostChild host;
  if (!host.start(executable,
                  QStringList{QStringLiteral("experiment"), QStringLiteral("load-host"), meshPath,
                              QStringLiteral("--clients"), QStringLiteral("1"), QStringLiteral("--nats"), server.url(),
                              QStringLiteral("--session=") + kSession, QStringLiteral("--nats-user"), config.hostUser,
                              QStringLiteral("--nats-password-file"), hostSecret} +
                      basisArguments)) {
    return QStringLiteral("cannot start the host process");
  }
  const QStringList hello =
      host.waitLine(QStringLiteral("load-host port"), std::chrono::minutes(30)).split(QLatin1Char(' '));
  if (hello.size() != 7) return QStringLiteral("the host process did not start hosting");
  result.vertices = hello[4].toInt();
  result.rows = hello[6].toInt();
  const QStringList relay = host.waitLine(QStringLiteral("load-host relay"), std::chrono::seconds(30)).split(' ');
  if (relay.size() != 3) return QStringLiteral("the host process does not relay");
  const QString pin = relay[2];

  const int processes = (settings.viewers + settings.viewersPerProcess - 1) / settings.viewersPerProcess;
  say(QStringLiteral("starting %1 viewers in %2 processes").arg(settings.viewers).arg(processes));
  QElapsedTimer joinClock;
  joinClock.start();
  std::vector<std::unique_ptr<HostChild>> children;
  std::vector<int> shares;
  for (int p = 0; p < processes; ++p) {
    const int share = settings.viewers / processes + (p < settings.viewers % processes ? 1 : 0);
    QStringList arguments{QStringLiteral("experiment"),
                          QStringLiteral("fanout-viewers"),
                          QStringLiteral("--viewers"),
                          QString::number(share),
                          QStringLiteral("--nats"),
                          server.url(),
                          QStringLiteral("--session=") + kSession,
                          QStringLiteral("--nats-user"),
                          config.viewerUser,
                          QStringLiteral("--nats-password-file"),
                          viewerSecret,
                          QStringLiteral("--pin"),
                          pin,
                          QStringLiteral("--pending"),
                          QString::number(settings.pendingLimit)};
    if (settings.sharedVerification) arguments << QStringLiteral("--shared-verify");
    auto child = std::make_unique<HostChild>();
    if (!child->start(executable, arguments)) {
      return QStringLiteral("cannot start viewer process %1").arg(p);
    }
    children.push_back(std::move(child));
    shares.push_back(share);
  }
  const auto startTimeout = std::chrono::milliseconds(static_cast<qint64>(settings.startTimeoutSeconds * 1000.0));
  for (std::size_t p = 0; p < children.size(); ++p) {
    if (children[p]->waitLine(QStringLiteral("fanout-viewers ready"), startTimeout).isEmpty())
      return QStringLiteral("viewer process %1 did not join").arg(p);
  }
  result.joinSeconds = static_cast<double>(joinClock.nsecsElapsed()) * 1e-9;
  say(QStringLiteral("%1 viewers joined in %2 s").arg(settings.viewers).arg(result.joinSeconds, 0, 'f', 1));
  for (const auto& child : children) child->command(QByteArrayLiteral("mark"));
  for (std::size_t p = 0; p < children.size(); ++p) {
    if (children[p]->waitLine(QStringLiteral("marked"), std::chrono::seconds(30)).isEmpty())
      return QStringLiteral("viewer process %1 did not answer").arg(p);
  }

  say(QStringLiteral("dragging for %1 s").arg(settings.seconds));
  const double serverCpu0 = childCpuSeconds(server.pid());
  QElapsedTimer dragClock;
  dragClock.start();
  host.command(QByteArrayLiteral("drag ") + QByteArray::number(settings.seconds));
  const QString done = host.waitLine(QStringLiteral("drag"),
                                     std::chrono::milliseconds(static_cast<qint64>(settings.seconds * 3000.0 + 60000)));
  if (done != QLatin1String("drag done")) return QStringLiteral("the host could not play its drag (%1)").arg(done);
  const double serverCpu1 = childCpuSeconds(server.pid());
  const double wall = static_cast<double>(dragClock.nsecsElapsed()) * 1e-9;
  result.serverCpuPercent = 100.0 * (serverCpu1 - serverCpu0) / wall;
  result.loadAverage = loadAverageNow();
  QThread::msleep(1000);  // the trailing frames reach the viewers

  host.command(QByteArrayLiteral("report"));
  const QJsonObject hostReport =
      QJsonDocument::fromJson(host.waitLine(QStringLiteral("{"), std::chrono::seconds(60)).toUtf8()).object();
  const QJsonObject relayReport = hostReport.value(QStringLiteral("relay")).toObject();
  if (relayReport.isEmpty()) return QStringLiteral("the host process did not report its relay");
  result.dragSeconds = hostReport.value(QStringLiteral("drag_seconds")).toDouble();
  if (result.dragSeconds > 0.0)
    result.hostCpuPercent = 100.0 * hostReport.value(QStringLiteral("cpu_seconds")).toDouble() / result.dragSeconds;
  result.framesPublished = relayReport.value(QStringLiteral("frames")).toInteger();
  result.keyframes = relayReport.value(QStringLiteral("keyframes")).toInteger();
  result.publishFailures = relayReport.value(QStringLiteral("failures")).toInteger();
  result.hostOutBytes = relayReport.value(QStringLiteral("out_bytes")).toInteger();
  result.hostPayloadBytes = relayReport.value(QStringLiteral("payload_bytes")).toInteger();
  result.audienceViewers = relayReport.value(QStringLiteral("audience_viewers")).toInt();

  for (const auto& child : children) child->command(QByteArrayLiteral("report"));
  for (std::size_t p = 0; p < children.size(); ++p) {
    const QJsonObject report =
        QJsonDocument::fromJson(children[p]->waitLine(QStringLiteral("{"), std::chrono::seconds(60)).toUtf8()).object();
    const QJsonArray rows = report.value(QStringLiteral("viewers")).toArray();
    if (rows.size() != shares[p]) return QStringLiteral("viewer process %1 did not report").arg(p);
    FanoutProcessRow process;
    process.viewers = shares[p];
    process.threads = report.value(QStringLiteral("threads")).toInt();
    const double seconds = report.value(QStringLiteral("wall_seconds")).toDouble();
    if (seconds > 0.0) process.cpuPercent = 100.0 * report.value(QStringLiteral("cpu_seconds")).toDouble() / seconds;
    process.rssMb = report.value(QStringLiteral("rss_mb")).toDouble();
    result.processes.push_back(process);
    for (const QJsonValue& value : rows) {
      const QJsonObject row = value.toObject();
      result.viewers.push_back({row.value(QStringLiteral("applied")).toInteger(),
                                row.value(QStringLiteral("lost")).toInteger(),
                                row.value(QStringLiteral("dropped_pending")).toInteger(),
                                row.value(QStringLiteral("bad_signature")).toInteger(),
                                row.value(QStringLiteral("latency_p50_ms")).toDouble(),
                                row.value(QStringLiteral("latency_p99_ms")).toDouble()});
    }
  }
  say(QStringLiteral("done"));
  return result;
}

QJsonObject fanoutResultJson(const FanoutResult& r) {
  std::vector<double> delivered, p50, p99;
  std::int64_t maxLost = 0, droppedPending = 0, badSignature = 0;
  for (const FanoutViewerRow& v : r.viewers) {
    delivered.push_back(r.framesPublished > 0 ? static_cast<double>(v.applied) / static_cast<double>(r.framesPublished)
                                              : 0.0);
    p50.push_back(v.latencyP50Ms);
    p99.push_back(v.latencyP99Ms);
    maxLost = std::max(maxLost, v.lost);
    droppedPending += v.droppedPending;
    badSignature += v.badSignature;
  }
  double viewerCpu = 0.0;
  int threads = 0;
  double rss = 0.0;
  for (const FanoutProcessRow& p : r.processes) {
    viewerCpu += p.cpuPercent;
    threads += p.threads;
    rss += p.rssMb;
  }
  const double frames = static_cast<double>(std::max<std::int64_t>(1, r.framesPublished));
  return {{QStringLiteral("mesh"), r.mesh},
          {QStringLiteral("vertices"), r.vertices},
          {QStringLiteral("rows"), r.rows},
          {QStringLiteral("viewers"), static_cast<int>(r.viewers.size())},
          {QStringLiteral("processes"), static_cast<int>(r.processes.size())},
          {QStringLiteral("viewers_per_process"), r.settings.viewersPerProcess},
          {QStringLiteral("pending_limit"), r.settings.pendingLimit},
          {QStringLiteral("shared_verification"), r.settings.sharedVerification},
          {QStringLiteral("seconds"), r.settings.seconds},
          {QStringLiteral("drag_seconds"), r.dragSeconds},
          {QStringLiteral("frames_published"), static_cast<qint64>(r.framesPublished)},
          {QStringLiteral("keyframes"), static_cast<qint64>(r.keyframes)},
          {QStringLiteral("publish_failures"), static_cast<qint64>(r.publishFailures)},
          {QStringLiteral("min_delivered_fraction"),
           delivered.empty() ? 0.0 : *std::min_element(delivered.begin(), delivered.end())},
          {QStringLiteral("median_delivered_fraction"), middleValue(delivered)},
          {QStringLiteral("max_lost"), static_cast<qint64>(maxLost)},
          {QStringLiteral("dropped_pending"), static_cast<qint64>(droppedPending)},
          {QStringLiteral("bad_signature"), static_cast<qint64>(badSignature)},
          {QStringLiteral("latency_p50_ms"), middleValue(p50)},
          {QStringLiteral("latency_p99_ms_median"), middleValue(p99)},
          {QStringLiteral("latency_p99_ms"), p99.empty() ? 0.0 : *std::max_element(p99.begin(), p99.end())},
          {QStringLiteral("host_cpu_pct"), r.hostCpuPercent},
          {QStringLiteral("host_upload_bytes_per_frame"), static_cast<double>(r.hostOutBytes) / frames},
          {QStringLiteral("host_payload_bytes_per_frame"), static_cast<double>(r.hostPayloadBytes) / frames},
          {QStringLiteral("server_cpu_pct"), r.serverCpuPercent},
          {QStringLiteral("viewer_processes_cpu_pct"), viewerCpu},
          {QStringLiteral("viewer_threads"), threads},
          {QStringLiteral("viewer_rss_mb"), rss},
          {QStringLiteral("audience_viewers"), r.audienceViewers},
          {QStringLiteral("join_s"), r.joinSeconds},
          {QStringLiteral("load_average"), r.loadAverage}};
}

}  // namespace sc::app
