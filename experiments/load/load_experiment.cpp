// The load experiment's driver (see load_experiment.h): the host child process, the client threads, the counts.

#include "experiments/load/load_experiment.h"

#include "experiments/load/host_child.h"

#include "app/cli/session_setup.h"
#include "session/engine/session_clock.h"
#include "session/net/session_client.h"

#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QThread>

#include <sys/resource.h>

#include <algorithm>
#include <map>
#include <memory>

namespace sc::app {
namespace {

using session::SessionClient;

constexpr int kJoinBatch = 4;  ///< clients joining at once (the host's per-address limit of handshakes is higher)

/// User + system CPU seconds of this process (every thread) so far.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// The machine's UDP counters (/proc/net/snmp "Udp:" lines): RcvbufErrors and SndbufErrors; zeros if unreadable.
std::pair<std::int64_t, std::int64_t> udpBufferErrors() {
  QFile file(QStringLiteral("/proc/net/snmp"));
  if (!file.open(QIODevice::ReadOnly)) return {0, 0};
  QList<QByteArray> names;
  for (const QByteArray& line : file.readAll().split('\n')) {
    if (!line.startsWith("Udp:")) continue;
    const QList<QByteArray> fields = line.mid(4).simplified().split(' ');
    if (names.isEmpty()) {
      names = fields;
      continue;
    }
    const auto value = [&](const char* name) {
      const qsizetype i = names.indexOf(QByteArray(name));
      return i >= 0 && i < fields.size() ? fields[i].toLongLong() : 0;
    };
    return {value("RcvbufErrors"), value("SndbufErrors")};
  }
  return {0, 0};
}

/// What one client counted so far (read in its own thread).
struct ClientCount {
  int peer = 0;
  std::int64_t received = 0, dropped = 0;
  double p50 = 0.0, p99 = 0.0;
  SessionClient::State state = SessionClient::State::Idle;
  QString error;
  std::uint32_t vertices = 0;
};

ClientCount countOf(SessionClient* client, bool clearLatency) {
  ClientCount count;
  QMetaObject::invokeMethod(
      client,
      [client, clearLatency, &count] {
        count.state = client->state();
        count.error = client->errorText();
        count.peer = client->peerId();
        count.vertices = client->levelVertexCount();
        if (count.state != SessionClient::State::Ready) return;
        const session::ReceiverReport r = client->channel().peek(session::sessionNow());
        count.received = r.received;
        count.dropped = static_cast<std::int64_t>(client->channel().droppedDatagrams());
        count.p50 = r.latencyP50Ms;
        count.p99 = r.latencyP99Ms;
        if (clearLatency) client->channel().clearLatency();
      },
      Qt::BlockingQueuedConnection);
  return count;
}

/// N clients spread over a few threads; everything they do runs in their threads.
class ClientPool {
 public:
  ClientPool(const LoadExperimentSettings& settings, quint16 port) {
    for (int t = 0; t < std::max(1, settings.clientThreads); ++t) {
      m_threads.push_back(std::make_unique<QThread>());
      m_threads.back()->start();
    }
    for (int i = 0; i < settings.clients; ++i) {
      session::SessionClientOptions options;
      options.port = port;
      options.name = QStringLiteral("load %1").arg(i + 1);
      options.levelFraction = settings.clientFraction;
      auto* client = new SessionClient(options);
      client->moveToThread(m_threads[static_cast<std::size_t>(i) % m_threads.size()].get());
      m_clients.push_back(client);
    }
  }
  /// Starts the clients `batch` at a time, each batch once the previous one is past its handshake (the host
  /// admits only a few unauthenticated connections per address at once); true when every client is Ready.
  bool join(int batch, std::chrono::milliseconds timeout) {
    for (std::size_t first = 0; first < m_clients.size(); first += static_cast<std::size_t>(batch)) {
      const std::size_t end = std::min(m_clients.size(), first + static_cast<std::size_t>(batch));
      for (std::size_t i = first; i < end; ++i) {
        QMetaObject::invokeMethod(m_clients[i], [client = m_clients[i]] { client->start(); });
      }
      const auto welcomed = [&] {
        for (std::size_t i = first; i < end; ++i) {
          if (countOf(m_clients[i], false).state < SessionClient::State::Loading) return false;
        }
        return true;
      };
      if (!waitUntil(welcomed, timeout)) return false;
    }
    return waitUntil(
        [this] {
          const std::vector<ClientCount> all = counts(false);
          return std::all_of(all.begin(), all.end(),
                             [](const ClientCount& c) { return c.state >= SessionClient::State::Ready; });
        },
        timeout);
  }
  ~ClientPool() {
    for (SessionClient* client : m_clients) {
      QMetaObject::invokeMethod(
          client,
          [client] {
            client->leave();
            client->deleteLater();  // deleted by its thread's event loop, or when the thread finishes
          },
          Qt::BlockingQueuedConnection);
    }
    for (auto& thread : m_threads) {
      thread->quit();
      thread->wait();
    }
  }
  std::vector<ClientCount> counts(bool clearLatency) const {
    std::vector<ClientCount> out;
    for (SessionClient* client : m_clients) out.push_back(countOf(client, clearLatency));
    return out;
  }

 private:
  std::vector<std::unique_ptr<QThread>> m_threads;
  std::vector<SessionClient*> m_clients;
};

}  // namespace

std::variant<LoadResult, QString> runLoadExperiment(const QString& executable, const QString& meshPath,
                                                    const QStringList& basisArguments,
                                                    const LoadExperimentSettings& settings,
                                                    const std::function<void(const QString&)>& progress) {
  const auto say = [&progress](const QString& line) {
    if (progress) progress(line);
  };
  LoadResult result;
  result.mesh = meshPath;
  result.settings = settings;
  say(QStringLiteral("starting the host process (basis of %1)").arg(meshPath));
  HostChild host;
  if (!host.start(executable, QStringList{QStringLiteral("experiment"), QStringLiteral("load-host"), meshPath,
                                          QStringLiteral("--clients"), QString::number(settings.clients)} +
                                  basisArguments)) {
    return QStringLiteral("cannot start the host process");
  }
  const QStringList hello =
      host.waitLine(QStringLiteral("load-host port"), std::chrono::minutes(30)).split(QLatin1Char(' '));
  if (hello.size() != 7) return QStringLiteral("the host process did not start hosting");
  const auto port = static_cast<quint16>(hello[2].toUInt());
  result.vertices = hello[4].toInt();
  result.rows = hello[6].toInt();

  say(QStringLiteral("joining %1 clients on %2 threads").arg(settings.clients).arg(settings.clientThreads));
  ClientPool pool(settings, port);
  pool.join(kJoinBatch, std::chrono::minutes(5));
  for (const ClientCount& c : pool.counts(false)) {
    if (c.state != SessionClient::State::Ready) return QStringLiteral("a client did not join: %1").arg(c.error);
    result.clientVertices = static_cast<int>(c.vertices);
  }
  waitUntil([] { return false; }, std::chrono::seconds(1));  // paths open, join keyframes in

  say(QStringLiteral("dragging for %1 s at 30 fps").arg(settings.seconds));
  const std::vector<ClientCount> before = pool.counts(true);
  const auto [rcvbufBefore, sndbufBefore] = udpBufferErrors();
  const double cpuBefore = processCpuSeconds();
  const std::int64_t wallBefore = session::sessionNow().count();
  host.command(QByteArrayLiteral("drag ") + QByteArray::number(settings.seconds));
  const bool dragged =
      host.waitLine(QStringLiteral("drag done"),
                    std::chrono::milliseconds(static_cast<int>(settings.seconds * 1000)) + std::chrono::seconds(30))
          .size() > 0;
  waitUntil([] { return false; }, std::chrono::milliseconds(500));  // the last datagrams in flight
  const double wall = 1e-6 * static_cast<double>(session::sessionNow().count() - wallBefore);
  result.clientCpuPercent = 100.0 * (processCpuSeconds() - cpuBefore) / wall;
  const auto [rcvbufAfter, sndbufAfter] = udpBufferErrors();
  result.udpRcvbufErrors = rcvbufAfter - rcvbufBefore;
  result.udpSndbufErrors = sndbufAfter - sndbufBefore;
  const std::vector<ClientCount> after = pool.counts(false);
  QFile loadAverage(QStringLiteral("/proc/loadavg"));
  if (loadAverage.open(QIODevice::ReadOnly)) result.loadAverage = loadAverage.readAll().split(' ').front().toDouble();
  if (!dragged) return QStringLiteral("the host did not finish the drag");

  host.command(QByteArrayLiteral("report"));
  const QString line = host.waitLine(QStringLiteral("{"), std::chrono::seconds(30));
  const QJsonObject report = QJsonDocument::fromJson(line.toUtf8()).object();
  if (report.isEmpty()) return QStringLiteral("the host process sent no report");
  result.dragSeconds = report[QStringLiteral("drag_seconds")].toDouble();
  result.hostCpuPercent =
      result.dragSeconds > 0 ? 100.0 * report[QStringLiteral("cpu_seconds")].toDouble() / result.dragSeconds : 0.0;
  result.frames = report[QStringLiteral("frames")].toInteger();
  result.hostSendErrors = report[QStringLiteral("send_errors")].toInteger();
  std::map<int, std::int64_t> sent;
  for (const QJsonValue& peer : report[QStringLiteral("peers")].toArray()) {
    sent[peer[QStringLiteral("peer")].toInt()] = peer[QStringLiteral("datagrams")].toInteger();
    result.datagramsSent += peer[QStringLiteral("datagrams")].toInteger();
  }
  for (std::size_t i = 0; i < after.size(); ++i) {
    LoadClientRow row;
    row.peer = after[i].peer;
    row.sentByHost = sent[row.peer];
    row.received = after[i].received - before[i].received;
    row.dropped = after[i].dropped - before[i].dropped;
    row.lossFraction =
        row.sentByHost > 0 ? 1.0 - static_cast<double>(row.received) / static_cast<double>(row.sentByHost) : 0.0;
    row.latencyP50Ms = after[i].p50;
    row.latencyP99Ms = after[i].p99;
    result.clients.push_back(row);
  }
  say(QStringLiteral("done"));
  return result;
}

}  // namespace sc::app
