// The host child of the load experiment (`shapecast-cli experiment load-host`, see load_experiment.h): a
// SessionHost on 127.0.0.1 whose own user plays the scripted drag at 30 fps on command, measuring its own CPU time.

#include "app/cli/relay_arguments.h"
#include "app/cli/session_setup.h"
#include "experiments/load/load_experiment.h"
#include "experiments/loss/loss_experiment.h"
#include "model/decimating_level_builder.h"
#include "session/engine/constraint_work.h"
#include "session/engine/host_engine.h"
#include "session/net/host_datagram_channel.h"
#include "session/net/nats_client.h"
#include "session/net/relay_publisher.h"
#include "session/net/session_host.h"
#include "session/net/tls_identity.h"
#include "spectral/hausdorff.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QJsonArray>
#include <QJsonDocument>
#include <QSocketNotifier>
#include <QTextStream>
#include <QTimer>

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace sc::app {
namespace {

/// User + system CPU seconds of this process (every thread) so far.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

void say(const QString& line) {
  QTextStream out(stdout);
  out << line << '\n';
  out.flush();
}

/// Keeps every k-th anchor, k as small as lets the set pass the host's constraint work limit
/// (HostEngineOptions::maxConstraintWork: (handle + anchor ids) · m²). The drag's anchors (every vertex beyond 40%
/// of the diagonal) pass it on the 23k dragon; on the 100k dragon they are about twice too many and the host refused
/// the drag. A thinned far region still holds the smooth spectral deformation in place.
void fitWorkLimit(spectral::ConstraintSet& set, int m) {
  std::size_t handleIds = 0;
  for (const spectral::HandleGroup& group : set.handles) handleIds += group.vertices.size();
  session::thinAnchors(set.anchors, handleIds, session::maxConstraintIds(m));
}

/// The scripted drag played by the host's own user, and what it measured.
class HostDrag {
 public:
  HostDrag(session::SessionHost& host, const session::HostModel& model)
      : m_host(host), m_script(defaultLossDrag(model.V)), m_diagonal(spectral::boundingBoxDiagonal(model.V)) {
    const std::variant<spectral::ConstraintSet, QString> resolved = resolveConstraints(m_script, model.V);
    if (const auto* set = std::get_if<spectral::ConstraintSet>(&resolved)) m_constraints = *set;
    fitWorkLimit(m_constraints, model.rowCount());
    m_timer.setSingleShot(true);
    m_timer.setTimerType(Qt::PreciseTimer);
    QObject::connect(&m_timer, &QTimer::timeout, &m_timer, [this] { step(); });
  }

  /// The relay publisher whose frames and bytes the report also counts (the fan-out experiment); may be null.
  void setRelay(const session::RelayPublisher* relay) { m_relay = relay; }

  /// Starts a drag of `seconds` (loops the 6 s script); false without the lock or constraints.
  bool start(double seconds) {
    if (m_constraints.handles.empty() || (!m_host.localLock().canDrag() && !m_host.requestLock())) return false;
    if (!m_host.localLock().canDrag() || !m_host.setConstraints(m_constraints)) return false;
    m_seconds = seconds;
    m_frame = 0;
    m_cpuAtStart = cpuSeconds();
    m_framesAtStart = m_host.counters().framesSent;
    m_errorsAtStart = m_host.channel().sendErrors();
    m_sentAtStart.clear();
    if (m_relay) {
      m_relayAtStart = m_relay->counters();
      m_relayTrafficAtStart = m_relay->connection()->traffic();
    }
    for (const session::PeerInfo& peer : m_host.peerList().peers)
      m_sentAtStart[peer.peerId] = m_host.channel().traffic(peer.peerId).datagramsSent;
    m_clock.start();
    step();
    return true;
  }

  /// The report line (see runLoadHost()).
  QJsonObject report() const {
    QJsonArray peers;
    for (const session::PeerInfo& peer : m_host.peerList().peers) {
      if (peer.peerId == session::kHostPeer) continue;
      const auto before = m_sentAtStart.find(peer.peerId);
      const std::uint64_t sent = m_host.channel().traffic(peer.peerId).datagramsSent;
      peers.append(QJsonObject{{QStringLiteral("peer"), static_cast<int>(peer.peerId)},
                               {QStringLiteral("datagrams"),
                                static_cast<qint64>(sent - (before == m_sentAtStart.end() ? 0 : before->second))}});
    }
    QJsonObject out{
        {QStringLiteral("drag_seconds"), m_dragSeconds},
        {QStringLiteral("cpu_seconds"), m_cpuSeconds},
        {QStringLiteral("frames"), static_cast<qint64>(m_host.counters().framesSent - m_framesAtStart)},
        {QStringLiteral("send_errors"), static_cast<qint64>(m_host.channel().sendErrors() - m_errorsAtStart)},
        {QStringLiteral("peers"), peers}};
    if (m_relay) out.insert(QStringLiteral("relay"), relayReport());
    return out;
  }

 private:
  /// Since the drag started, up to now: {"frames", "keyframes", "payload_bytes" (the publisher's count),
  /// "out_messages", "out_bytes" (the NATS connection's, stats included), "failures", "audience": the viewers'
  /// aggregate as the host sees it}.
  QJsonObject relayReport() const {
    const session::RelayPublisherCounters& now = m_relay->counters();
    const session::NatsTraffic traffic = m_relay->connection()->traffic();
    const session::RelayAudienceSummary audience = m_relay->audience();
    return {
        {QStringLiteral("frames"), static_cast<qint64>(now.frames - m_relayAtStart.frames)},
        {QStringLiteral("keyframes"), static_cast<qint64>(now.keyframes - m_relayAtStart.keyframes)},
        {QStringLiteral("payload_bytes"), static_cast<qint64>(now.bytes - m_relayAtStart.bytes)},
        {QStringLiteral("failures"), static_cast<qint64>(now.failures - m_relayAtStart.failures)},
        {QStringLiteral("out_messages"), static_cast<qint64>(traffic.outMessages - m_relayTrafficAtStart.outMessages)},
        {QStringLiteral("out_bytes"), static_cast<qint64>(traffic.outBytes - m_relayTrafficAtStart.outBytes)},
        {QStringLiteral("audience_viewers"), audience.viewers},
        {QStringLiteral("audience_loss_max"), audience.lossFraction.max},
        {QStringLiteral("audience_latency_p99_ms_median"), audience.latencyP99Ms.median}};
  }

  void step() {
    const double t = static_cast<double>(m_frame) / m_script.fps;
    if (t > m_seconds) {
      m_dragSeconds = static_cast<double>(m_clock.nsecsElapsed()) * 1e-9;
      m_cpuSeconds = cpuSeconds() - m_cpuAtStart;
      say(QStringLiteral("drag done"));
      return;
    }
    const double period = m_script.frames.back().t;
    const spectral::HandleTransform pose = transformAt(poseAt(m_script, std::fmod(t, period)), m_diagonal);
    const std::vector<spectral::HandleTransform> poses(m_constraints.handles.size(), pose);
    m_host.drag(poses);
    ++m_frame;
    const double dueMs = 1000.0 * static_cast<double>(m_frame) / m_script.fps;
    m_timer.start(std::max(0, static_cast<int>(std::lround(dueMs - static_cast<double>(m_clock.elapsed())))));
  }

  session::SessionHost& m_host;
  DragScript m_script;
  double m_diagonal;
  spectral::ConstraintSet m_constraints;
  QTimer m_timer;
  QElapsedTimer m_clock;
  double m_seconds = 0.0;
  int m_frame = 0;
  double m_cpuAtStart = 0.0, m_cpuSeconds = 0.0, m_dragSeconds = 0.0;
  std::uint64_t m_framesAtStart = 0, m_errorsAtStart = 0;
  std::map<session::PeerId, std::uint64_t> m_sentAtStart;
  const session::RelayPublisher* m_relay = nullptr;
  session::RelayPublisherCounters m_relayAtStart;
  session::NatsTraffic m_relayTrafficAtStart;
};

}  // namespace

int runLoadHost(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("experiment load-host"),
                           QStringLiteral("The host child of `experiment load` (commands on stdin)."));
  const QCommandLineOption clients(QStringLiteral("clients"), QStringLiteral("clients to admit"), QStringLiteral("N"),
                                   QStringLiteral("8"));
  command.parser().addOption(clients);
  const RelayArguments relayArguments;  // the fan-out experiment: also relay through NATS
  relayArguments.addTo(command);
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  std::optional<session::RelayPublisherOptions> relay;
  if (!relayArguments.readPublisher(command, QStringLiteral("shapecast load host"), relay)) return kExitUsage;
  bool ok = false;
  const int maxPeers = command.parser().value(clients).toInt(&ok);
  if (!ok || maxPeers < 1 || maxPeers > session::kMaxPeers - 1) {
    command.error(QStringLiteral("--clients takes 1..%1").arg(session::kMaxPeers - 1));
    return kExitUsage;
  }
  const std::shared_ptr<const session::HostModel> model = loadHostModel(command, command.meshPath(), exitCode);
  if (!model) return exitCode;

  session::SessionHostOptions options;
  options.levelBuilder = session::LevelBuilder{model::levelTargetList, model::decimatedLevel};
  options.address = QHostAddress::LocalHost;
  options.maxPeers = maxPeers;
  options.hostName = QStringLiteral("load host");
  options.idleRefresh = std::chrono::hours(1);  // only drag frames on UDP: the per-client counts compare exactly
  session::SessionHost host(model, options);
  QString error;
  if (!host.start(&error)) {
    command.error(QStringLiteral("cannot host: %1").arg(error));
    return kExitNetwork;
  }
  HostDrag drag(host, *model);
  std::unique_ptr<session::RelayPublisher> publisher;
  if (relay) {
    publisher = std::make_unique<session::RelayPublisher>(host, std::move(*relay));
    if (!publisher->start(&error)) {
      command.error(QStringLiteral("cannot relay: %1").arg(error));
      return kExitNetwork;
    }
    drag.setRelay(publisher.get());
  }
  say(QStringLiteral("load-host port %1 vertices %2 rows %3")
          .arg(host.tcpPort())
          .arg(model->vertexCount())
          .arg(model->rowCount()));
  // The fan-out experiment's viewers pin this certificate.
  if (publisher) say(QStringLiteral("load-host relay %1").arg(session::formatFingerprint(host.fingerprint())));

  QByteArray pending;
  QSocketNotifier input(STDIN_FILENO, QSocketNotifier::Read);
  QObject::connect(&input, &QSocketNotifier::activated, &input, [&] {
    char buffer[256];
    const ssize_t n = ::read(STDIN_FILENO, buffer, sizeof buffer);
    if (n <= 0) {  // the parent went away
      input.setEnabled(false);
      QCoreApplication::exit(kExitNetwork);
      return;
    }
    pending.append(buffer, static_cast<qsizetype>(n));
    for (qsizetype end = pending.indexOf('\n'); end >= 0; end = pending.indexOf('\n')) {
      const QList<QByteArray> words = pending.left(end).trimmed().split(' ');
      pending.remove(0, end + 1);
      if (words.front() == "drag" && words.size() == 2) {
        if (!drag.start(words[1].toDouble())) say(QStringLiteral("drag failed"));
      } else if (words.front() == "report") {
        say(QString::fromUtf8(QJsonDocument(drag.report()).toJson(QJsonDocument::Compact)));
        host.shutdown();
        QTimer::singleShot(100, QCoreApplication::instance(), &QCoreApplication::quit);
      }
    }
  });
  const int code = QCoreApplication::exec();
  if (publisher) {
    publisher.reset();
    session::natsShutdown();
  }
  return code;
}

}  // namespace sc::app
