// ClientController, part 1: joining (SessionClient and its distortion meter), the frame path passed down, the
// lifecycle, the lock and what this user sends, and how the host's certificate was trusted (session::KnownHosts).
// Levels, network conditions and statistics are in client_controller_figures.cpp.
#include "app/gui/client_controller.h"

#include "app/gui/vertex_id_lists.h"
#include "session/engine/constraint_work.h"
#include "session/net/distortion_meter.h"
#include "session/net/session_client.h"
#include "session/net/tls_known_hosts.h"
#include "session/wire/handle_transforms.h"

#include <cmath>
#include <vector>

namespace sc::app {

ClientController::ClientController(QObject* parent) : SessionController(parent) {}

ClientController::~ClientController() {
  if (m_client != nullptr) {
    m_client->disconnect(this);
    m_client->leave();
  }
}

bool ClientController::join(const JoinSettings& settings) {
  if (state() != State::Idle) return false;
  setLevelTarget(settings.level);
  session::SessionClientOptions options;
  options.host = settings.host;
  options.port = settings.port;
  options.name = settings.name;
  options.password = settings.password;
  options.level = settings.level;
  options.levelFraction = settings.levelFraction;
  options.impairment = settings.impairment;
  options.fingerprint = settings.fingerprint;
  options.trustOnFirstUse = true;  // as shapecast-cli join: remember the first fingerprint, refuse a change
  options.knownHostsFile = settings.knownHostsFile;
  options.progressive = true;  // the smallest level first, live, then the requested one (issue 17 item 4)
  m_joinFraction = settings.levelFraction;
  m_joinSettings = settings;
  m_joinSettings.password.reset();
  if (!settings.fingerprint.isEmpty()) {
    m_joinTrust = HostTrust::Pinned;
  } else {
    const bool known = session::KnownHosts(settings.knownHostsFile).lookup(settings.host, settings.port).has_value();
    m_joinTrust = known ? HostTrust::Known : HostTrust::FirstUse;
  }
  m_client = new session::SessionClient(options, this);
  m_meter = new session::DistortionMeter(*m_client, session::DistortionMeter::Mode::Live, m_client);
  connectClient();
  changeState(State::Connecting);
  emit progress(0, tr("Connecting to %1:%2").arg(settings.host).arg(settings.port));
  m_client->start();
  return true;
}

void ClientController::connectClient() {
  using session::SessionClient;
  connect(m_client, &SessionClient::stateChanged, this, &ClientController::onClientState);
  // the frame path, one way: the client's shared level and its frames go down as they are
  connect(m_client, &SessionClient::displayLevelChanged, this,
          [this](const spectral::SharedDisplayLevel& level) { showLevel(level); });
  connect(m_client, &SessionClient::frameUpdated, this,
          [this](const spectral::DisplayFrame& frame) { showFrame(frame); });
  connect(m_client, &SessionClient::levelReady, this, &ClientController::onLevelReady);
  connect(m_client, &SessionClient::levelFailed, this, [this](const QString& reason) {
    emit levelDownload(-1, QString());
    emit failed(tr("The new resolution could not be loaded: %1").arg(reason));
  });
  connect(m_client, &SessionClient::modelProgress, this, [this](quint64 received, quint64 total) {
    const int percent = total == 0 ? 0 : static_cast<int>(100 * received / total);
    if (state() != State::Live) {
      emit progress(percent, tr("Downloading the model"));
      return;
    }
    // Behind the shown level: the requested one of a progressive join, or a resolution switch.
    const std::uint32_t vertices = m_client->transferVertexCount();
    const bool full = m_client->session() && vertices == m_client->session()->vertexCount;
    emit levelDownload(percent, full ? tr("Full detail") : tr("%L1 vertices").arg(vertices));
  });
  connect(m_client, &SessionClient::lockChanged, this, &ClientController::onLockChanged);
  connect(m_client, &SessionClient::editLogChanged, this, &ClientController::editLogChanged);
  connect(m_client, &SessionClient::peersChanged, this, &ClientController::peersChanged);
  connect(m_client, &SessionClient::levelsChanged, this, &ClientController::levelsChanged);
  connect(m_client, &SessionClient::presenceReceived, this, &ClientController::presenceReceived);
}

void ClientController::onClientState() {
  using S = session::SessionClient::State;
  const S s = m_client->state();
  if (s == S::Failed) {
    if (state() == State::Live) {
      fail(tr("The session ended: %1").arg(m_client->errorText()));
    } else {
      fail(tr("Could not join the session: %1").arg(m_client->errorText()));
    }
  } else if (s == S::Left && !leaving()) {
    // The host's Leave says why (ended, removed you): ClientEngine's leaveText().
    fail(m_client->errorText().isEmpty() ? tr("The host ended the session.") : m_client->errorText());
  }
}

void ClientController::onLevelReady() {
  editor().levelChanged();  // the handle and anchors (full ids) shown on the new level; nothing is sent
  if (state() == State::Connecting) {
    if (m_joinFraction && *m_joinFraction > 0.0 && *m_joinFraction < 1.0 && m_client->session()) {
      setLevelTarget(static_cast<std::uint32_t>(std::round(*m_joinFraction * m_client->session()->vertexCount)));
    }
    emit progress(100, tr("Joined"));
    changeState(State::Live);
  }
  if (!m_client->levelPending()) emit levelDownload(-1, QString());  // the requested level is in
  emit statsChanged();
  emit meshChanged();
  emit peersChanged();
  emit lockChanged();
}

void ClientController::cancel() {
  if (state() != State::Connecting) return;
  markCancelledByUser();
  fail(tr("Cancelled."));
}

void ClientController::stop() {
  if (m_client != nullptr) m_client->leave();
}

session::PeerId ClientController::selfId() const { return m_client != nullptr ? m_client->peerId() : session::kNoPeer; }

// ---------------------------------------------------------------------------------------------------- lock, edits

void ClientController::sendPresence(const session::Presence& presence) {
  if (state() == State::Live) m_client->sendPresence(presence);
}

bool ClientController::requestLock() { return state() == State::Live && m_client->requestLock(); }

bool ClientController::release() { return m_client->releaseLock(); }

const session::LockClient* ClientController::lockClient() const {
  return m_client != nullptr ? m_client->lock() : nullptr;
}

std::vector<session::PeerId> ClientController::lockHolders() const {
  const session::LockClient* lock = lockClient();
  return state() == State::Live && lock != nullptr ? lock->holders() : std::vector<session::PeerId>{};
}

spectral::LocatedFullVertices ClientController::fullVertices(const spectral::DisplayVertexIds& displayed) const {
  const spectral::ResolutionLevel* shown = level();
  return shown != nullptr ? spectral::locateFullVertices(*shown, displayed) : spectral::LocatedFullVertices{};
}

spectral::DisplayVertexIds ClientController::displayedVertices(const spectral::LocatedFullVertices& full) const {
  const spectral::ResolutionLevel* shown = level();
  return shown != nullptr ? spectral::displayedVertices(*shown, full) : spectral::DisplayVertexIds{};
}

bool ClientController::sendConstraints(const spectral::FullVertexIds& handle, const spectral::FullVertexIds& anchors) {
  if (!m_client->session()) return false;
  // Within the host's work bound (constraint_work.h): a brush on a dense mesh anchors more ids than it allows.
  std::vector<std::uint32_t> held = spectral::plainIndices<spectral::FullVertexTag>(anchors);
  session::thinAnchors(held, handle.size(), session::maxConstraintIds(m_client->session()->rowCount));
  return m_client->sendConstraints({spectral::plainIndices<spectral::FullVertexTag>(handle)}, std::move(held));
}

bool ClientController::sendPose(const spectral::HandleTransform& pose) {
  return m_client->sendDrag({session::toWire(0, pose)});
}

bool ClientController::endStroke() { return m_client != nullptr && m_client->endStroke(); }

session::EditLog ClientController::editLog() const {
  return state() == State::Live ? m_client->editLog() : session::EditLog{};
}

bool ClientController::requestEdit(session::EditAction action) {
  if (state() != State::Live || dragging()) return false;
  return m_client->requestEdit(action);
}

// ---------------------------------------------------------------------------------------------------- identity

QByteArray ClientController::hostFingerprint() const {
  return m_client != nullptr ? m_client->hostFingerprint() : QByteArray();
}

HostTrust ClientController::hostTrust() const {
  // The handshake starts only once the certificate passed the fingerprint check (SessionClient::onEncrypted).
  if (m_client == nullptr || m_client->handshake().state() == session::ClientHandshake::State::SendHello) {
    return HostTrust::None;
  }
  return m_joinTrust;
}

bool ClientController::fingerprintRefused() const {
  // A certificate was seen but the handshake never started: the fingerprint check is the only thing in between.
  return m_client != nullptr && m_client->state() == session::SessionClient::State::Failed &&
         !m_client->hostFingerprint().isEmpty() &&
         m_client->handshake().state() == session::ClientHandshake::State::SendHello;
}

std::optional<JoinSettings> ClientController::passwordRetry() const {
  if (m_client == nullptr || m_client->state() != session::SessionClient::State::Failed) return std::nullopt;
  const session::ClientHandshake& handshake = m_client->handshake();
  const bool asked = handshake.failure() == session::ClientFailure::PasswordRequired;
  const bool refused = handshake.failure() == session::ClientFailure::RefusedByHost && handshake.refusal() &&
                       handshake.refusal()->reason == session::RefuseReason::WrongPassword;
  if (!asked && !refused) return std::nullopt;
  return m_joinSettings;
}

}  // namespace sc::app
