// SessionController: what both roles share: the lifecycle (state, failure, leave), the lock as this user sees it,
// the display data last pushed down, and the defaults of the role-specific queries.
#include "app/gui/session_controller.h"

#include "app/gui/lock_text.h"
#include "session/engine/edit_history.h"
#include "session/engine/lock_client.h"

#include <QTimer>

#include <utility>

namespace sc::app {

namespace {

const Eigen::MatrixXd kEmptyV;
const Eigen::MatrixXi kEmptyF;

}  // namespace

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
  connect(m_secondTimer, &QTimer::timeout, this, &SessionController::statsChanged);
}

SessionController::~SessionController() = default;

// ---------------------------------------------------------------------------------------------------- lifecycle

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
  m_editor.endDrag();
  changeState(State::Failed);
  stop();
  emit lockChanged();
  emit failed(message);
}

void SessionController::leave() {
  if (m_state != State::Preparing && m_state != State::Connecting && m_state != State::Live) return;
  m_leaving = true;
  m_editor.endDrag();
  stop();
  changeState(State::Left);
  emit lockChanged();
  emit peersChanged();
}

// ---------------------------------------------------------------------------------------------------- lock

bool SessionController::releaseLock() {
  if (m_state != State::Live) return false;
  m_editor.endDrag();
  return release();
}

bool SessionController::canDrag() const {
  const session::LockClient* lock = lockClient();
  return m_state == State::Live && lock != nullptr && lock->canDrag();
}

bool SessionController::lockWanted() const {
  const session::LockClient* lock = lockClient();
  return m_state == State::Live && lock != nullptr && lock->state() != session::LockState::Idle;
}

QString SessionController::lockText() const {
  const session::LockClient* lock = lockClient();
  if (m_state != State::Live || lock == nullptr) return {};
  return app::lockText(*lock, lockHolders(), selfId(), peers());
}

QString SessionController::lockActionText() const {
  const session::LockClient* lock = lockClient();
  return m_state == State::Live && lock != nullptr ? app::lockActionText(*lock)
                                                   : app::lockActionText(session::LockClient(0));
}

bool SessionController::holdsLock(session::PeerId peer) const {
  const std::vector<session::PeerId> holders = lockHolders();
  return std::find(holders.begin(), holders.end(), peer) != holders.end();
}

void SessionController::onLockChanged() {
  const session::LockClient* lock = lockClient();
  if (lock != nullptr && lock->lastRefusal() && lock->lastRefusal()->serial != m_refusalsShown) {
    m_refusalsShown = lock->lastRefusal()->serial;
    emit constraintsRefused(app::refusalText(*lock->lastRefusal(), peers()));
  }
  m_editor.lockChanged(canDrag());
  emit lockChanged();
  emit peersChanged();  // the peers view shows the holder
}

// ---------------------------------------------------------------------------------------------------- edits

std::optional<session::EditLogEntry> SessionController::undoableStep() const {
  return session::undoableIn(editLog(), selfId(), role() == Role::Host);  // the host moderates the shared history
}

std::optional<session::EditLogEntry> SessionController::redoableStep() const {
  return session::redoableIn(editLog(), selfId());
}

// ---------------------------------------------------------------------------------------------------- display

void SessionController::showLevel(spectral::SharedDisplayLevel level) {
  m_level = std::move(level);
  emit displayLevelChanged(m_level);
}

void SessionController::showFrame(spectral::DisplayFrame frame) {
  m_frame = std::move(frame);
  emit frameChanged(m_frame);
}

const Eigen::MatrixXd& SessionController::displayRestPositions() const {
  return m_level ? m_level->level.restV : kEmptyV;
}

const Eigen::MatrixXi& SessionController::displayFaces() const { return m_level ? m_level->level.F : kEmptyF; }

std::vector<float> SessionController::positions() const {
  if (!m_level) return {};
  return spectral::reconstructed(*m_level, m_frame);
}

Eigen::MatrixXd SessionController::coefficients() const { return m_frame.Z.cast<double>(); }

// ---------------------------------------------------------------------------------------------------- defaults

bool SessionController::setLevel(std::uint32_t /*target*/) { return false; }

bool SessionController::setNetworkConditions(double /*loss*/, double /*burstLength*/, int /*delayMs*/,
                                             double /*rateMbit*/) {
  return false;
}

double SessionController::sentKbps(session::PeerId /*peer*/) const { return 0.0; }

}  // namespace sc::app
