#include "experiments/loss/loss_experiment.h"

#include "app/cli/session_setup.h"
#include "model/decimating_level_builder.h"
#include "session/engine/session_clock.h"
#include "session/net/distortion_meter.h"
#include "session/net/host_datagram_channel.h"
#include "session/net/session_host.h"
#include "session/wire/handle_transforms.h"
#include "spectral/hausdorff.h"

#include <QThread>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace sc::app {
namespace {

struct PeerIdAndLevel {
  session::PeerId peer = session::kNoPeer;
  std::uint32_t vertices = 0;
};

using session::SessionClient;

constexpr auto kJoinTimeout = std::chrono::seconds(120);

/// Runs `f` in `object`'s thread and returns its result (blocking; `object` must live in another, running thread).
template <typename F>
auto inThreadOf(QObject* object, F f) {
  std::invoke_result_t<F> result{};
  QMetaObject::invokeMethod(object, std::move(f), Qt::BlockingQueuedConnection, &result);
  return result;
}

/// One of the six measuring clients of a loss ratio. Each runs in its own thread, as separate client processes
/// would, so one client's reconstruction never delays another's datagrams (the latency figure).
struct MeasuringClient {
  SessionClient* client = nullptr;            ///< lives in `thread`; handed back to the main thread before deletion
  session::DistortionMeter* meter = nullptr;  ///< child of client
  std::unique_ptr<QThread> thread;
  bool full = true;
  session::Concealment concealment = session::Concealment::HoldLast;
  std::uint64_t offeredBefore = 0;
  std::uint64_t droppedBefore = 0;
  std::uint64_t bytesBefore = 0;
  PeerIdAndLevel identity;
};

constexpr session::Concealment kConcealments[] = {session::Concealment::HoldLast, session::Concealment::ZeroFill,
                                                  session::Concealment::Extrapolate};

QString concealmentName(session::Concealment c) { return QString::fromLatin1(session::toString(c)); }

session::ImpairmentSettings impairmentFor(const LossExperimentSettings& settings, double loss) {
  session::ImpairmentSettings impairment;
  impairment.loss = loss;
  impairment.burst = settings.burst;
  impairment.burstLength = settings.burstLength;
  impairment.seed = settings.seed;
  return impairment;
}

/// Measures every pair of every client on `threads` threads; returns per client the distortions (percent).
std::vector<std::vector<double>> measure(const std::vector<const spectral::ResolutionLevel*>& levels,
                                         const std::vector<std::vector<session::DistortionPair>>& pairs,
                                         double diagonal, int threads) {
  struct Job {
    std::size_t client, pair;
  };
  std::vector<Job> jobs;
  std::vector<std::vector<double>> out(pairs.size());
  for (std::size_t c = 0; c < pairs.size(); ++c) {
    out[c].resize(pairs[c].size());
    for (std::size_t p = 0; p < pairs[c].size(); ++p) jobs.push_back({c, p});
  }
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t j = next++; j < jobs.size(); j = next++) {
      const session::DistortionPair& pair = pairs[jobs[j].client][jobs[j].pair];
      out[jobs[j].client][jobs[j].pair] =
          session::distortionPercent(*levels[jobs[j].client], pair.shown, pair.exact, diagonal);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  return out;
}

}  // namespace

DragScript defaultLossDrag(const Eigen::MatrixXd& rest) {
  Eigen::Index extremity = 0;
  rest.col(0).maxCoeff(&extremity);
  DragScript script;
  script.handles.push_back(HandleSelection{{}, SphereSelection{static_cast<int>(extremity), 5.0}});
  script.anchors.fartherThan = FartherThanSelection{static_cast<int>(extremity), 40.0};
  script.frames = {DragKeyframe{0.0, {}}, DragKeyframe{3.0, {Eigen::Vector3d(0.0, 15.0, 0.0), {}}},
                   DragKeyframe{6.0, {}}};
  script.fps = 30.0;
  return script;
}

std::variant<std::vector<LossRow>, QString> runLossExperiment(std::shared_ptr<const session::HostModel> model,
                                                              const LossExperimentSettings& settings,
                                                              const std::function<void(const QString&)>& progress) {
  const auto say = [&progress](const QString& line) {
    if (progress) progress(line);
  };
  session::SessionHostOptions hostOptions;
  hostOptions.levelBuilder = session::LevelBuilder{model::levelTargetList, model::decimatedLevel};
  hostOptions.address = QHostAddress::LocalHost;
  hostOptions.referenceEvery = 1;
  hostOptions.hostName = QStringLiteral("experiment host");
  session::SessionHost host(model, hostOptions);
  QString error;
  if (!host.start(&error)) return QStringLiteral("cannot host: %1").arg(error);

  const double diagonal = spectral::boundingBoxDiagonal(model->V);
  const DragScript script = defaultLossDrag(model->V);
  const std::variant<spectral::ConstraintSet, QString> resolved = resolveConstraints(script, model->V);
  if (const QString* why = std::get_if<QString>(&resolved)) return *why;
  const spectral::ConstraintSet& constraints = std::get<spectral::ConstraintSet>(resolved);
  const auto lowWanted = static_cast<std::uint32_t>(std::lround(settings.lowFraction * model->vertexCount()));

  const auto clientOptions = [&](const QString& name, std::uint32_t level) {
    session::SessionClientOptions options;
    options.host = QStringLiteral("127.0.0.1");
    options.port = host.tcpPort();
    options.name = name;
    options.level = level;
    return options;
  };
  const auto joined = [](SessionClient& client) {
    client.start();
    waitUntil([&client] { return client.state() >= SessionClient::State::Ready; }, kJoinTimeout);
    return client.state() == SessionClient::State::Ready;
  };

  // The driver holds the lock for the whole experiment (its LockClient renews the lease).
  SessionClient driver(clientOptions(QStringLiteral("driver"), lowWanted));
  if (!joined(driver)) return QStringLiteral("the driver could not join: %1").arg(driver.errorText());
  const WireConstraints wire = wireConstraints(constraints);

  const auto holdLock = [&driver, &wire] {
    // Before each drag: hold the lock (taken again should the lease have been lost) and set the constraints.
    if (!driver.lock()->canDrag()) {
      driver.requestLock();
      if (!waitUntil([&driver] { return driver.lock()->canDrag(); }, std::chrono::seconds(10))) return false;
    }
    driver.sendConstraints(wire.groups, wire.anchors);
    return true;
  };

  std::vector<LossRow> rows;
  for (double loss : settings.losses) {
    say(QStringLiteral("loss %1: joining %2 clients").arg(loss).arg(2 * std::size(kConcealments)));
    std::vector<MeasuringClient> clients;
    for (bool full : {true, false}) {
      for (session::Concealment c : kConcealments) {
        MeasuringClient m;
        session::SessionClientOptions options = clientOptions(
            QStringLiteral("%1 %2").arg(full ? QStringLiteral("full") : QStringLiteral("low"), concealmentName(c)),
            full ? 0 : lowWanted);
        options.concealment = c;
        options.impairment = impairmentFor(settings, loss);
        m.client = new SessionClient(options);
        m.meter = new session::DistortionMeter(*m.client, session::DistortionMeter::Mode::Record, m.client);
        m.full = full;
        m.concealment = c;
        m.thread = std::make_unique<QThread>();
        m.client->moveToThread(m.thread.get());
        m.thread->start();
        QMetaObject::invokeMethod(m.client, [client = m.client] { client->start(); });
        clients.push_back(std::move(m));
      }
    }
    const auto allClients = [&clients](const std::function<bool(SessionClient&)>& test) {
      return std::all_of(clients.begin(), clients.end(), [&test](const MeasuringClient& m) {
        return inThreadOf(m.client, [&test, client = m.client] { return test(*client); });
      });
    };
    const bool ready =
        waitUntil([&] { return allClients([](SessionClient& c) { return c.state() >= SessionClient::State::Ready; }); },
                  kJoinTimeout);
    if (!ready || !allClients([](SessionClient& c) { return c.state() == SessionClient::State::Ready; })) {
      return QStringLiteral("a measuring client could not join");
    }
    // Path open and the first (refresh) frame in, so the drag starts from a displayed shape.
    waitUntil([&] { return allClients([](SessionClient& c) { return c.channel().hasFrame(); }); },
              std::chrono::seconds(5));
    if (!holdLock()) return QStringLiteral("the driver did not get the lock");
    waitUntil([] { return false; }, std::chrono::milliseconds(50));  // the constraints are in

    const std::uint32_t firstFrame = host.currentFrame() + 1;
    const std::uint64_t framesBefore = host.counters().framesSent;
    for (MeasuringClient& m : clients) {
      m.identity = inThreadOf(m.client, [&m] {
        m.meter->clearRecorded();
        m.client->channel().clearLatency();  // latency of the drag's frames only, not of the joins
        m.offeredBefore = m.client->channel().impairment()->offered();
        m.droppedBefore = m.client->channel().impairment()->dropped();
        return PeerIdAndLevel{m.client->peerId(), m.client->levelVertexCount()};
      });
      m.bytesBefore = host.channel().traffic(m.identity.peer).bytesSent;
    }
    say(QStringLiteral("loss %1: dragging").arg(loss));
    playDragScript(driver, script, wire.groups.size(), diagonal);
    waitUntil([] { return false; }, std::chrono::milliseconds(300));  // the last datagrams and keyframes
    const std::uint32_t lastFrame = host.currentFrame();
    const double frames = static_cast<double>(host.counters().framesSent - framesBefore);

    std::vector<const spectral::ResolutionLevel*> levels;
    std::vector<std::vector<session::DistortionPair>> pairs;
    std::vector<LossRow> lossRows;
    for (MeasuringClient& m : clients) {
      LossRow row;
      row.loss = loss;
      row.concealment = concealmentName(m.concealment);
      row.fullLevel = m.full;
      row.levelVertices = static_cast<int>(m.identity.vertices);
      row.payloadBytesPerFrame =
          frames > 0 ? static_cast<double>(host.channel().traffic(m.identity.peer).bytesSent - m.bytesBefore) / frames
                     : 0.0;
      std::vector<session::DistortionPair> recorded = inThreadOf(m.client, [&m, &row] {
        const session::NetworkImpairment* impairment = m.client->channel().impairment();
        const double offered = static_cast<double>(impairment->offered() - m.offeredBefore);
        row.measuredLoss = offered > 0 ? static_cast<double>(impairment->dropped() - m.droppedBefore) / offered : 0.0;
        row.latencyP99Ms = m.client->channel().peek(session::sessionNow()).latencyP99Ms;
        return m.meter->takeRecorded();
      });
      std::erase_if(recorded, [&](const session::DistortionPair& p) {
        return static_cast<std::int32_t>(p.frame - firstFrame) < 0 ||
               static_cast<std::int32_t>(lastFrame - p.frame) < 0;
      });
      // The client leaves and comes back to this thread (so that it can be deleted here once its thread ended).
      QThread* mainThread = QThread::currentThread();
      QMetaObject::invokeMethod(
          m.client,
          [client = m.client, mainThread] {
            client->leave();
            client->moveToThread(mainThread);
          },
          Qt::BlockingQueuedConnection);
      m.thread->quit();
      m.thread->wait();
      levels.push_back(m.client->level());
      pairs.push_back(std::move(recorded));
      lossRows.push_back(row);
    }
    say(QStringLiteral("loss %1: measuring %2 frames per client").arg(loss).arg(pairs.front().size()));
    // Off the event loop's thread, so that the host and the driver keep their heartbeats and lease meanwhile.
    std::vector<std::vector<double>> distortions;
    std::atomic<bool> measured{false};
    std::thread worker([&] {
      distortions = measure(levels, pairs, diagonal, settings.threads);
      measured = true;
    });
    waitUntil([&measured] { return measured.load(); }, std::chrono::hours(1));
    worker.join();

    for (std::size_t c = 0; c < clients.size(); ++c) {
      LossRow& row = lossRows[c];
      row.frames = static_cast<int>(distortions[c].size());
      for (std::size_t i = 0; i < distortions[c].size(); ++i) {
        const double d = distortions[c][i];
        if (d > row.hdMaxPct) {
          row.hdMaxPct = d;
          row.hdMaxFrame = static_cast<int>(pairs[c][i].frame - firstFrame);
        }
        row.hdMeanPct += d / std::max(1, row.frames);
      }
      rows.push_back(row);
      delete clients[c].client;
    }
  }
  driver.releaseLock();
  driver.leave();
  host.shutdown();
  waitUntil([] { return false; }, std::chrono::milliseconds(100));
  return rows;
}

}  // namespace sc::app
