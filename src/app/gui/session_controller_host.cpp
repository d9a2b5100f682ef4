// SessionController, host side: preparation (HostPreparation on a worker thread), starting the SessionHost, the
// restoring of a saved session's state, and the host's own display (X̂ + H·Z of the full level on every new frame).
#include "app/gui/session_controller.h"

#include "app/gui/host_preparation.h"
#include "app/gui/session_snapshot.h"
#include "model/decimating_level_builder.h"
#include "model/session_file.h"
#include "session/engine/host_model.h"
#include "session/net/session_client.h"
#include "session/net/session_host.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/resolution_level.h"

#include <utility>

namespace sc::app {

bool SessionController::host(const HostSettings& settings) {
  if (m_state != State::Idle) return false;
  m_role = Role::Host;
  m_hostSettings = settings;
  changeState(State::Preparing);
  emit progress(0, tr("Loading %1").arg(settings.meshPath));
  m_preparation = std::make_unique<HostPreparation>();
  m_preparation->start(
      settings, this, [this](int percent, const QString& what) { emit progress(percent, what); },
      [this](const std::shared_ptr<PreparedHost>& prepared) { finishPreparation(prepared); });
  return true;
}

void SessionController::finishPreparation(const std::shared_ptr<PreparedHost>& prepared) {
  m_preparation->join();
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
  m_saved = prepared->saved;
  m_fullLevel = std::move(prepared->full);
  m_rest = spectral::interleavedPositions(m_model->V);
  m_hostPositions = m_rest;
  m_hostPositionsStale = false;

  session::SessionHostOptions options;
  options.levelBuilder = session::LevelBuilder{model::levelTargetList, model::decimatedLevel};
  options.tcpPort = m_hostSettings.port;
  options.password = m_hostSettings.password;
  options.hostName = m_hostSettings.name.isEmpty() ? QStringLiteral("host") : m_hostSettings.name;
  if (m_saved) options.deformer.mode = m_saved->mode;
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
  if (m_saved) restoreSavedSession();
}

void SessionController::restoreSavedSession() {
  const auto restore = [this] {
    if (m_saved->current && !restoreHostDeformation(toHostDeformation(*m_saved->current))) {
      emit failed(tr("The saved shape could not be restored (the deformer refused its constraints)."));
    }
    emit savedSessionRestored();
  };
  if (!m_saved->current) {
    emit savedSessionRestored();
    return;
  }
  // The host's own lock request is granted at once when nobody holds the lock (a fresh host); otherwise the state
  // is restored when it is granted.
  requestLock();
  if (canDrag()) {
    restore();
    return;
  }
  auto connection = std::make_shared<QMetaObject::Connection>();
  *connection = connect(this, &SessionController::lockChanged, this, [this, restore, connection] {
    if (!canDrag()) return;
    disconnect(*connection);
    restore();
  });
}

QByteArray SessionController::hostFingerprint() const {
  if (m_host != nullptr) return m_host->fingerprint();
  return m_client != nullptr ? m_client->hostFingerprint() : QByteArray();
}

void SessionController::onHostFrame() {
  if (m_host == nullptr || !m_fullLevel) return;
  const Eigen::MatrixXd& Z = m_host->coefficients();
  if (Z.rows() != m_fullLevel->K.cols() || Z.cols() != 3) return;
  if (m_lastZ.rows() == Z.rows() && m_lastZ.cols() == Z.cols() && m_lastZ == Z) return;  // idle refresh
  m_lastZ = Z;
  m_hostPositionsStale = true;  // reconstructed by positions(), if anyone asks
  emit positionsChanged();
}

}  // namespace sc::app
