#include "app/gui/session_controller.h"

#include "model/cache_location.h"
#include "model/mesh_decimation.h"
#include "model/mesh_loader.h"
#include "session/distortion_meter.h"
#include "session/handle_transforms.h"
#include "session/host_model.h"
#include "session/session_client.h"
#include "session/session_clock.h"
#include "session/session_host.h"
#include "session/wire_format.h"
#include "spectral/basis_pipeline.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/resolution_level.h"

#include <QFile>
#include <QMetaObject>
#include <QTimer>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <utility>
#include <variant>

namespace sc::app {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::vector<float> interleaved(const Eigen::MatrixXd& V) {
  std::vector<float> out(static_cast<std::size_t>(V.rows()) * 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(i) * 3 + static_cast<std::size_t>(c)] = float(V(i, c));
  }
  return out;
}

QString ordinal(std::uint32_t n) {
  if (n % 100 >= 11 && n % 100 <= 13) return QStringLiteral("%1th").arg(n);
  switch (n % 10) {
    case 1:
      return QStringLiteral("%1st").arg(n);
    case 2:
      return QStringLiteral("%1nd").arg(n);
    case 3:
      return QStringLiteral("%1rd").arg(n);
    default:
      return QStringLiteral("%1th").arg(n);
  }
}

const Eigen::MatrixXd kEmptyV;
const Eigen::MatrixXi kEmptyF;

}  // namespace

/// What the host's preparation thread hands back.
struct SessionController::Prepared {
  std::shared_ptr<session::HostModel> model;
  std::unique_ptr<spectral::ResolutionLevel> full;
  QString error;
  bool cancelled = false;
};

QString toString(SessionController::State state) {
  switch (state) {
    case SessionController::State::Idle:
      return QStringLiteral("not in a session");
    case SessionController::State::Preparing:
      return QStringLiteral("preparing");
    case SessionController::State::Connecting:
      return QStringLiteral("connecting");
    case SessionController::State::Live:
      return QStringLiteral("live");
    case SessionController::State::Left:
      return QStringLiteral("left");
    case SessionController::State::Failed:
      return QStringLiteral("failed");
  }
  return {};
}

SessionController::SessionController(QObject* parent) : QObject(parent) {
  m_secondTimer = new QTimer(this);
  m_secondTimer->setInterval(1000);
  connect(m_secondTimer, &QTimer::timeout, this, &SessionController::everySecond);
}

SessionController::~SessionController() {
  if (m_cancel) m_cancel->store(true);
  joinWorker();
  if (m_host != nullptr) m_host->shutdown();
  if (m_client != nullptr) m_client->leave();
}

void SessionController::joinWorker() {
  if (m_worker.joinable()) m_worker.join();
}

void SessionController::changeState(State next) {
  if (m_state == next) return;
  m_state = next;
  if (next == State::Live) {
    m_secondTimer->start();
  } else {
    m_secondTimer->stop();
  }
  emit stateChanged(next);
}

void SessionController::fail(const QString& message) {
  if (m_state == State::Failed || m_state == State::Left) return;
  m_errorText = message;
  m_dragging = false;
  changeState(State::Failed);
  if (m_host != nullptr) m_host->shutdown();
  if (m_client != nullptr) m_client->leave();
  emit lockChanged();
  emit failed(message);
}

// ---------------------------------------------------------------------------------------------------- hosting

bool SessionController::host(const HostSettings& settings) {
  if (m_state != State::Idle) return false;
  m_role = Role::Host;
  m_hostSettings = settings;
  changeState(State::Preparing);
  m_cancel = std::make_shared<std::atomic<bool>>(false);
  emit progress(0, tr("Loading %1").arg(settings.meshPath));

  const std::shared_ptr<std::atomic<bool>> cancel = m_cancel;
  m_worker = std::thread([this, settings, cancel] {
    auto prepared = std::make_shared<Prepared>();
    const auto report = [this](int percent, const QString& what) {
      QMetaObject::invokeMethod(
          this, [this, percent, what] { emit progress(percent, what); }, Qt::QueuedConnection);
    };
    const auto deliver = [this, prepared] {
      QMetaObject::invokeMethod(
          this, [this, prepared] { finishPreparation(prepared); }, Qt::QueuedConnection);
    };
    try {
      model::MeshLoadResult loaded =
          model::loadMesh(std::filesystem::path(QFile::encodeName(settings.meshPath).toStdString()));
      if (const auto* error = std::get_if<model::MeshError>(&loaded)) {
        prepared->error = QString::fromStdString(error->message);
        deliver();
        return;
      }
      auto mesh = std::get<model::LoadedMesh>(std::move(loaded));
      const auto n = static_cast<int>(mesh.V.rows());
      if (n < 4) {
        prepared->error = tr("The mesh has too few vertices (%1) to host.").arg(n);
        deliver();
        return;
      }
      if (cancel->load()) {
        prepared->cancelled = true;
        deliver();
        return;
      }
      report(10, tr("Computing the harmonic basis"));
      spectral::BasisOptions options;
      options.m = std::clamp(settings.m, 1, std::min(n - 1, session::kMaxRows));
      int lastPercent = 10;
      options.progress = [cancel, report, &lastPercent](double fraction) {
        const int percent = 10 + static_cast<int>(85.0 * std::clamp(fraction, 0.0, 1.0));
        if (percent != lastPercent) {
          lastPercent = percent;
          report(percent, tr("Computing the harmonic basis"));
        }
        return !cancel->load();
      };
      std::optional<std::filesystem::path> cacheDir;
      if (settings.useBasisCache) cacheDir = model::basisCacheDirectory();
      spectral::BasisComputation basis = spectral::basisForMesh(mesh.V, mesh.F, options, cacheDir);
      if (basis.result.status == spectral::BasisStatus::Cancelled || cancel->load()) {
        prepared->cancelled = true;
        deliver();
        return;
      }
      if (!basis.result.ok()) {
        prepared->error = tr("The harmonic basis could not be computed (%1): %2")
                              .arg(QString::fromLatin1(spectral::toString(basis.result.status)),
                                   QString::fromStdString(basis.result.message));
        deliver();
        return;
      }
      report(95, tr("Preparing the display"));
      auto model = std::make_shared<session::HostModel>();
      model->V = std::move(mesh.V);
      model->F = std::move(mesh.F);
      model->basis = std::move(basis.result.basis);
      model->operators = std::move(basis.operators);
      prepared->full = std::make_unique<spectral::ResolutionLevel>(
          spectral::fullResolutionLevel(model->V, model->F, model->basis.vectors));
      prepared->model = std::move(model);
    } catch (const std::exception& e) {
      prepared->error = tr("Preparing the session failed: %1").arg(QString::fromLocal8Bit(e.what()));
    }
    deliver();
  });
  return true;
}

void SessionController::finishPreparation(const std::shared_ptr<Prepared>& prepared) {
  joinWorker();
  if (m_state != State::Preparing) return;  // cancelled or left meanwhile
  if (prepared->cancelled) {
    fail(tr("Cancelled."));
    return;
  }
  if (!prepared->error.isEmpty() || !prepared->model) {
    fail(tr("Could not host %1: %2").arg(m_hostSettings.meshPath, prepared->error));
    return;
  }
  m_model = prepared->model;
  m_fullLevel = std::move(prepared->full);
  m_rest = interleaved(m_model->V);
  m_hostPositions = m_rest;

  session::SessionHostOptions options;
  options.tcpPort = m_hostSettings.port;
  options.password = m_hostSettings.password;
  options.hostName = m_hostSettings.name.isEmpty() ? QStringLiteral("host") : m_hostSettings.name;
  m_host = new session::SessionHost(m_model, options, this);
  QString error;
  if (!m_host->start(&error)) {
    fail(tr("Could not host on TCP port %1: %2").arg(m_hostSettings.port).arg(error));
    return;
  }
  connect(m_host, &session::SessionHost::frameSent, this, &SessionController::onHostFrame);
  connect(m_host, &session::SessionHost::lockChanged, this, &SessionController::onLockChanged);
  connect(m_host, &session::SessionHost::peersChanged, this, &SessionController::peersChanged);
  connect(m_host, &session::SessionHost::statsReported, this, &SessionController::statsChanged);
  m_lastZ = m_host->coefficients();
  emit progress(100, tr("Hosting"));
  changeState(State::Live);
  emit meshChanged();
  emit positionsChanged();
  emit peersChanged();
  emit lockChanged();
  emit hostingStarted(m_host->tcpPort());
}

void SessionController::onHostFrame() {
  if (m_host == nullptr || !m_fullLevel) return;
  const Eigen::MatrixXd& Z = m_host->coefficients();
  if (Z.rows() != m_fullLevel->K.cols() || Z.cols() != 3) return;
  if (m_lastZ.rows() == Z.rows() && m_lastZ.cols() == Z.cols() && m_lastZ == Z) return;  // idle refresh
  m_lastZ = Z;
  const Eigen::MatrixXf Zf = Z.cast<float>();
  const auto start = Clock::now();
  m_hostPositions.resize(m_rest.size());
  spectral::reconstructInterleaved(m_fullLevel->K, m_rest, Zf, m_hostPositions);
  m_reconstructionMs = millisecondsSince(start);
  emit positionsChanged();
}

// ---------------------------------------------------------------------------------------------------- joining

bool SessionController::join(const JoinSettings& settings) {
  if (m_state != State::Idle) return false;
  m_role = Role::Client;
  m_levelTarget = settings.level;
  session::SessionClientOptions options;
  options.host = settings.host;
  options.port = settings.port;
  options.name = settings.name;
  options.password = settings.password;
  options.level = settings.level;
  options.levelFraction = settings.levelFraction;
  options.impairment = settings.impairment;
  m_joinFraction = settings.levelFraction;
  m_client = new session::SessionClient(options, this);
  m_meter = new session::DistortionMeter(*m_client, session::DistortionMeter::Mode::Live, m_client);
  connect(m_client, &session::SessionClient::stateChanged, this, &SessionController::onClientState);
  connect(m_client, &session::SessionClient::levelReady, this, &SessionController::onClientLevel);
  connect(m_client, &session::SessionClient::levelFailed, this,
          [this](const QString& reason) { emit failed(tr("The new resolution could not be loaded: %1").arg(reason)); });
  connect(m_client, &session::SessionClient::modelProgress, this, [this](quint64 received, quint64 total) {
    const int percent = total == 0 ? 0 : static_cast<int>(100 * received / total);
    emit progress(percent, tr("Downloading the model"));
  });
  connect(m_client, &session::SessionClient::positionsUpdated, this, &SessionController::positionsChanged);
  connect(m_client, &session::SessionClient::lockChanged, this, &SessionController::onLockChanged);
  connect(m_client, &session::SessionClient::peersChanged, this, &SessionController::peersChanged);
  changeState(State::Connecting);
  emit progress(0, tr("Connecting to %1:%2").arg(settings.host).arg(settings.port));
  m_client->start();
  return true;
}

void SessionController::onClientState() {
  using S = session::SessionClient::State;
  const S s = m_client->state();
  if (s == S::Failed) {
    if (m_state == State::Live) {
      fail(tr("The session ended: %1").arg(m_client->errorText()));
    } else {
      fail(tr("Could not join the session: %1").arg(m_client->errorText()));
    }
  } else if (s == S::Left) {
    if (!m_leaving) {
      fail(tr("The host ended the session."));
    }
  }
}

void SessionController::onClientLevel() {
  m_clientRestV = m_client->level() != nullptr ? m_client->level()->restV : Eigen::MatrixXd();
  m_constraintsSent = false;  // ids of the previous level mean nothing on the new one
  m_handle.clear();
  m_anchors.clear();
  if (m_state == State::Connecting) {
    if (m_joinFraction && *m_joinFraction > 0.0 && *m_joinFraction < 1.0 && m_client->session()) {
      m_levelTarget = static_cast<std::uint32_t>(std::round(*m_joinFraction * m_client->session()->vertexCount));
    }
    emit progress(100, tr("Joined"));
    changeState(State::Live);
  }
  everySecond();  // a first timing sample and stats
  emit meshChanged();
  emit positionsChanged();
  emit peersChanged();
  emit lockChanged();
}

const spectral::ResolutionLevel* SessionController::clientLevel() const {
  return m_client != nullptr ? m_client->level() : nullptr;
}

// ---------------------------------------------------------------------------------------------------- ending

void SessionController::cancel() {
  if (m_state == State::Preparing) {
    if (m_cancel) m_cancel->store(true);
    // finishPreparation() reports the cancellation once the worker stops.
  } else if (m_state == State::Connecting) {
    fail(tr("Cancelled."));
  }
}

void SessionController::leave() {
  if (m_state != State::Preparing && m_state != State::Connecting && m_state != State::Live) return;
  m_leaving = true;
  m_dragging = false;
  if (m_cancel) m_cancel->store(true);
  if (m_host != nullptr) m_host->shutdown();
  if (m_client != nullptr) m_client->leave();
  changeState(State::Left);
  emit lockChanged();
  emit peersChanged();
}

quint16 SessionController::tcpPort() const {
  return m_host != nullptr && m_state == State::Live ? m_host->tcpPort() : 0;
}

session::PeerId SessionController::selfId() const {
  if (m_host != nullptr) return session::kHostPeer;
  if (m_client != nullptr) return m_client->peerId();
  return session::kNoPeer;
}

// ---------------------------------------------------------------------------------------------------- lock

bool SessionController::requestLock() {
  if (m_state != State::Live) return false;
  if (m_host != nullptr) return m_host->requestLock();
  return m_client != nullptr && m_client->requestLock();
}

bool SessionController::releaseLock() {
  if (m_state != State::Live) return false;
  m_dragging = false;
  if (m_host != nullptr) return m_host->releaseLock();
  return m_client != nullptr && m_client->releaseLock();
}

bool SessionController::canDrag() const {
  if (m_state != State::Live) return false;
  if (m_host != nullptr) return m_host->localLock().canDrag();
  return m_client != nullptr && m_client->lock() != nullptr && m_client->lock()->canDrag();
}

bool SessionController::lockWanted() const {
  if (m_state != State::Live) return false;
  const session::LockClient* lock = nullptr;
  if (m_host != nullptr) lock = &m_host->localLock();
  if (m_client != nullptr) lock = m_client->lock();
  return lock != nullptr && lock->state() != session::LockState::Idle;
}

session::PeerId SessionController::lockHolder() const {
  if (m_state != State::Live) return session::kNoPeer;
  if (m_host != nullptr) return m_host->lockHolder();
  if (m_client != nullptr && m_client->lock() != nullptr) return m_client->lock()->holder();
  return session::kNoPeer;
}

std::vector<session::PeerId> SessionController::lockQueue() const {
  if (m_state != State::Live || m_host == nullptr) return {};
  return {m_host->lockQueue().begin(), m_host->lockQueue().end()};
}

QString SessionController::lockText() const {
  if (m_state != State::Live) return {};
  const session::LockClient* lock = m_host != nullptr ? &m_host->localLock() : m_client->lock();
  if (lock == nullptr) return {};
  QString text;
  const session::PeerId holder = lockHolder();
  if (holder == selfId() && lock->canDrag()) {
    text = tr("You hold the lock");
  } else if (holder == session::kNoPeer) {
    text = tr("Lock free");
  } else {
    QString name = tr("peer %1").arg(holder);
    for (const session::PeerInfo& peer : peers().peers) {
      if (peer.peerId == holder && !peer.name.isEmpty()) name = peer.name;
    }
    text = tr("Lock held by %1").arg(name);
  }
  switch (lock->state()) {
    case session::LockState::Requested:
      text += tr(" — requesting…");
      break;
    case session::LockState::Queued:
      text += tr(" — you are %1 in the queue").arg(ordinal(lock->queuePosition()));
      break;
    case session::LockState::Releasing:
      text += tr(" — releasing…");
      break;
    case session::LockState::Idle:
    case session::LockState::Held:
      break;
  }
  return text;
}

void SessionController::onLockChanged() {
  const bool held = canDrag();
  if (held && !m_hadLock) {
    m_constraintsSent = false;
    sendConstraints();
  }
  if (!held) m_dragging = false;
  m_hadLock = held;
  emit lockChanged();
  emit peersChanged();  // the peers view shows the holder
}

// ---------------------------------------------------------------------------------------------------- constraints

std::vector<int> SessionController::toFullIds(const std::vector<int>& displayed) const {
  std::vector<int> ids;
  ids.reserve(displayed.size());
  if (m_host != nullptr) {
    const int n = m_model ? m_model->vertexCount() : 0;
    for (int id : displayed) {
      if (id >= 0 && id < n) ids.push_back(id);
    }
  } else if (const spectral::ResolutionLevel* level = clientLevel()) {
    const spectral::BarycentricMap& P = level->P;
    for (int id : displayed) {
      if (id < 0 || id >= P.rows()) continue;
      int best = -1;
      double bestWeight = -1.0;
      for (spectral::BarycentricMap::InnerIterator it(P, id); it; ++it) {
        if (it.value() > bestWeight) {
          bestWeight = it.value();
          best = static_cast<int>(it.col());
        }
      }
      if (best >= 0) ids.push_back(best);
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

bool SessionController::setHandle(std::vector<int> displayedIds) {
  m_handle = std::move(displayedIds);
  m_constraintsSent = false;
  return sendConstraints();
}

bool SessionController::setAnchors(std::vector<int> displayedIds) {
  m_anchors = std::move(displayedIds);
  m_constraintsSent = false;
  return sendConstraints();
}

bool SessionController::setSelection(std::vector<int> handle, std::vector<int> anchors) {
  m_handle = std::move(handle);
  m_anchors = std::move(anchors);
  m_constraintsSent = false;
  return sendConstraints();
}

bool SessionController::sendConstraints() {
  if (m_constraintsSent || !canDrag()) return false;
  const std::vector<int> handle = toFullIds(m_handle);
  if (handle.empty()) return false;
  std::vector<int> anchors = toFullIds(m_anchors);
  // a vertex cannot be both: the handle wins
  anchors.erase(std::remove_if(anchors.begin(), anchors.end(),
                               [&handle](int id) { return std::binary_search(handle.begin(), handle.end(), id); }),
                anchors.end());
  bool sent = false;
  if (m_host != nullptr) {
    spectral::ConstraintSet set;
    set.handles.push_back({handle});
    set.anchors = anchors;
    sent = m_host->setConstraints(set);
  } else if (m_client != nullptr) {
    sent = m_client->sendConstraints({std::vector<std::uint32_t>(handle.begin(), handle.end())},
                                     std::vector<std::uint32_t>(anchors.begin(), anchors.end()));
  }
  m_constraintsSent = sent;
  if (sent && m_host != nullptr) {
    m_sentHandle = handle;
    m_sentAnchors = anchors;
  }
  if (sent) {  // a new constraint set starts from rest
    m_baseRotation = m_lastRotation = Eigen::Matrix3d::Identity();
    m_baseTranslation = m_lastTranslation = Eigen::Vector3d::Zero();
  }
  return sent;
}

bool SessionController::beginDrag() {
  if (!canDrag() || m_handle.empty()) return false;
  if (!m_constraintsSent && !sendConstraints()) return false;
  m_baseRotation = m_lastRotation;
  m_baseTranslation = m_lastTranslation;
  m_dragging = true;
  return true;
}

bool SessionController::dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation) {
  if (!m_dragging || !canDrag()) return false;
  const spectral::HandleTransform pose{m_baseTranslation + translation, rotation * m_baseRotation};
  bool sent = false;
  if (m_host != nullptr) {
    sent = m_host->drag(std::span<const spectral::HandleTransform>(&pose, 1));
  } else if (m_client != nullptr) {
    sent = m_client->sendDrag({session::toWire(0, pose)});
  }
  if (sent) {
    m_lastRotation = pose.rotation;
    m_lastTranslation = pose.translation;
  }
  return sent;
}

void SessionController::endDrag() { m_dragging = false; }

std::optional<HostDeformation> SessionController::hostDeformation() const {
  if (m_host == nullptr || !m_constraintsSent) return std::nullopt;
  return HostDeformation{m_sentHandle, m_sentAnchors, m_lastTranslation, m_lastRotation};
}

bool SessionController::restoreHostDeformation(const HostDeformation& state) {
  if (m_host == nullptr || m_dragging || !canDrag() || state.handle.empty()) return false;
  spectral::ConstraintSet set;
  set.handles.push_back({state.handle});
  set.anchors = state.anchors;
  if (!m_host->setConstraints(set)) return false;
  const spectral::HandleTransform pose{state.translation, state.rotation};
  if (!m_host->drag(std::span<const spectral::HandleTransform>(&pose, 1))) return false;
  m_handle = m_sentHandle = state.handle;
  m_anchors = m_sentAnchors = state.anchors;
  m_constraintsSent = true;
  m_baseRotation = m_lastRotation = pose.rotation;
  m_baseTranslation = m_lastTranslation = pose.translation;
  return true;
}

// ---------------------------------------------------------------------------------------------------- display

const spectral::ResolutionLevel* SessionController::level() const {
  if (m_host != nullptr) return m_fullLevel.get();
  return clientLevel();
}

const Eigen::MatrixXd& SessionController::displayRestPositions() const {
  if (m_host != nullptr && m_model) return m_model->V;
  if (clientLevel() != nullptr) return m_clientRestV;
  return kEmptyV;
}

const Eigen::MatrixXi& SessionController::displayFaces() const {
  if (m_host != nullptr && m_model) return m_model->F;
  if (const spectral::ResolutionLevel* l = clientLevel()) return l->F;
  return kEmptyF;
}

std::span<const float> SessionController::positions() const {
  if (m_host != nullptr) return m_hostPositions;
  if (m_client != nullptr) return m_client->positions();
  return {};
}

Eigen::MatrixXd SessionController::coefficients() const {
  if (m_host != nullptr) return m_host->coefficients();
  if (m_client != nullptr && m_client->channel().hasFrame()) return m_client->channel().coefficients();
  return {};
}

std::vector<LevelChoice> SessionController::levels() const {
  std::vector<LevelChoice> out;
  int n = 0;
  if (m_model) n = m_model->vertexCount();
  if (m_client != nullptr && m_client->session()) n = static_cast<int>(m_client->session()->vertexCount);
  if (n <= 0) return out;
  out.push_back({0, tr("Full (%1 vertices)").arg(n)});
  if (m_host != nullptr) return out;
  for (int target : model::levelTargets(n)) {
    if (target >= n) continue;
    out.push_back({static_cast<std::uint32_t>(target), tr("≈ %1 vertices").arg(target)});
  }
  return out;
}

bool SessionController::setLevel(std::uint32_t target) {
  if (m_client == nullptr || m_state != State::Live) return false;
  if (!m_client->requestResolution(target)) return false;
  m_levelTarget = target;
  m_dragging = false;
  return true;
}

// ---------------------------------------------------------------------------------------------------- network

bool SessionController::setNetworkConditions(double loss, double burstLength, int delayMs) {
  if (m_client == nullptr) return false;
  loss = std::isfinite(loss) ? std::clamp(loss, 0.0, 1.0) : 0.0;
  burstLength = std::isfinite(burstLength) ? std::max(1.0, burstLength) : 1.0;
  delayMs = std::max(0, delayMs);
  std::optional<session::ImpairmentSettings> settings;
  if (loss > 0.0 || delayMs > 0) {
    settings.emplace();
    settings->loss = loss;
    settings->burst = burstLength > 1.0;
    settings->burstLength = burstLength;
    settings->delay = std::chrono::milliseconds(delayMs);
    // A fresh seed per change, so that returning to a setting does not replay the same losses.
    const std::optional<session::ImpairmentSettings>& previous = m_client->impairment();
    settings->seed = previous ? previous->seed + 1 : 1;
  }
  m_client->setImpairment(settings);
  emit networkConditionsChanged();
  return true;
}

NetworkConditions SessionController::networkConditions() const {
  NetworkConditions conditions;
  if (m_client == nullptr || !m_client->impairment()) return conditions;
  const session::ImpairmentSettings& s = *m_client->impairment();
  conditions.loss = s.loss;
  conditions.burstLength = s.burst ? s.burstLength : 1.0;
  conditions.delayMs = static_cast<int>(s.delay.count());
  return conditions;
}

// ---------------------------------------------------------------------------------------------------- peers

session::PeerList SessionController::peers() const {
  if (m_host != nullptr && m_state == State::Live) return m_host->peerList();
  if (m_client != nullptr && m_state == State::Live) return m_client->peers();
  return {};
}

std::optional<session::StatsReport> SessionController::stats(session::PeerId peer) const {
  if (m_state != State::Live) return std::nullopt;
  if (m_host != nullptr) return m_host->stats(peer);
  if (m_client == nullptr || peer != m_client->peerId() || !m_client->channel().isOpen()) return std::nullopt;
  const auto figure = [](double v) { return std::isfinite(v) && v > 0.0 ? v : 0.0; };
  const session::ReceiverReport r = m_client->channel().peek(session::sessionNow());
  session::StatsReport s;
  s.vertexCount = m_client->levelVertexCount();
  s.framesApplied = static_cast<std::uint32_t>(m_client->channel().framesApplied());
  s.received = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.received));
  s.lost = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.cumulativeLost));
  s.late = r.late;
  s.dropped = m_client->channel().droppedDatagrams();
  s.lossFraction = figure(r.lossFraction);
  s.jitterMs = figure(r.jitterMs);
  s.payloadKbpsIn = figure(r.payloadKbps);
  s.wireKbpsIn = figure(r.wireKbps);
  s.framesPerSecond = figure(r.framesPerSecond);
  s.latencyP50Ms = figure(r.latencyP50Ms);
  s.latencyP99Ms = figure(r.latencyP99Ms);
  if (m_meter != nullptr) {
    s.hdMaxPct = figure(m_meter->summary().maxPct);
    s.hdMeanPct = figure(m_meter->summary().meanPct);
    s.hdLastPct = figure(m_meter->summary().lastPct);
  }
  return s;
}

void SessionController::everySecond() {
  if (m_client != nullptr) {
    // SessionClient reconstructs internally; time the same reconstruction (same K, same Z) on a scratch buffer.
    const spectral::ResolutionLevel* l = clientLevel();
    if (l != nullptr && m_client->channel().hasFrame()) {
      const Eigen::MatrixXf Zf = m_client->channel().coefficients().cast<float>();
      if (Zf.rows() == l->K.cols() && Zf.cols() == 3) {
        const std::span<const float> rest = m_client->positions();  // same size as X̂'
        m_scratch.resize(rest.size());
        const auto start = Clock::now();
        spectral::reconstructInterleaved(l->K, rest, Zf, m_scratch);
        m_reconstructionMs = millisecondsSince(start);
      }
    }
  }
  emit statsChanged();
}

}  // namespace sc::app
