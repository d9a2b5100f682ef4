// ClientEngine: the state machine, the handshake, the message dispatcher and the user's commands. Levels, keyframes
// and frames are in client_engine_levels.cpp; heartbeats, stats, silence and renewals in client_engine_cadence.cpp.

#include "session/engine/client_engine.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sc::session {
namespace {

Millis toMillis(Micros now) { return std::chrono::duration_cast<Millis>(now); }

QString describe(MessageType type) {
  return QStringLiteral("0x%1").arg(static_cast<int>(type), 2, 16, QLatin1Char('0'));
}

QString protocolError(const QString& what) { return QStringLiteral("protocol error from the host: %1").arg(what); }

}  // namespace

QString leaveText(const Leave& leave) {
  QString text;
  switch (leave.reason) {
    case LeaveReason::Kicked:
      text = QStringLiteral("The host removed you from the session.");
      break;
    case LeaveReason::HostEnded:
    case LeaveReason::ClientLeft:  // not what a host says; read as the end of the session
      text = QStringLiteral("The host ended the session.");
      break;
  }
  if (!leave.text.isEmpty()) text += QStringLiteral(" (%1)").arg(leave.text);
  return text;
}

ClientEngine::ClientEngine(ClientEngineConfig config)
    : m_config(std::move(config)),
      m_handshake(ClientHandshakeConfig{m_config.name, m_config.password, {}, m_config.minPbkdf2Iterations}) {}

// --- lifecycle

ClientActions ClientEngine::start() {
  ClientActions out;
  if (m_state != ClientState::Idle) return out;
  changeState(ClientState::Connecting, out);
  out.emplace_back(client_action::Connect{});
  return out;
}

ClientActions ClientEngine::onSecured(QByteArray channelBinding, Micros now) {
  ClientActions out;
  m_handshake = ClientHandshake(
      ClientHandshakeConfig{m_config.name, m_config.password, std::move(channelBinding), m_config.minPbkdf2Iterations});
  m_config.password.reset();  // the handshake holds the one copy now, until its proof
  m_lastHeard = now;
  changeState(ClientState::Handshaking, out);
  send(m_handshake.start(), out);
  return out;
}

ClientActions ClientEngine::onDatagramsOpened(Micros now) {
  ClientActions out;
  if (m_state != ClientState::Handshaking || !m_session) return out;
  changeState(ClientState::Loading, out);
  if (m_config.levelFraction) {
    const double fraction = *m_config.levelFraction;
    const double wanted = fraction >= 1.0 || !(fraction > 0.0) ? 0.0 : std::round(fraction * m_session->vertexCount);
    m_config.level = static_cast<std::uint32_t>(std::max(0.0, wanted));
  }
  if (m_config.progressive && m_config.level != kSmallestLevel) {  // the smallest level first, the wanted one next
    m_deferredLevel = m_config.level;
    send(ResolutionRequest{kSmallestLevel}, out);
  } else {
    send(ResolutionRequest{m_config.level}, out);
  }
  m_nextSecond = now + kSecond;
  return out;
}

ClientActions ClientEngine::onClosed() {
  if (m_handshake.state() == ClientHandshake::State::Refused) return fail(m_handshake.errorText());
  if (live()) return fail(QStringLiteral("host lost: the connection to the host closed without warning"));
  return fail(QStringLiteral("the host closed the connection"));
}

ClientActions ClientEngine::onTransportError(const QString& text) {
  return fail(live() ? QStringLiteral("host lost: %1").arg(text) : text);
}

ClientActions ClientEngine::fail(const QString& reason) {
  ClientActions out;
  fail(reason, out);
  return out;
}

void ClientEngine::fail(const QString& reason, ClientActions& out) {
  if (m_state == ClientState::Left || m_state == ClientState::Failed) return;
  m_errorText = reason;
  out.emplace_back(client_action::CloseDatagrams{});
  changeState(ClientState::Failed, out);
  out.emplace_back(client_action::Disconnect{false});
  out.emplace_back(client_action::Failed{reason});
}

ClientActions ClientEngine::leave() {
  ClientActions out;
  if (m_state == ClientState::Idle || m_state == ClientState::Left || m_state == ClientState::Failed) return out;
  if (live())
    send(Leave{LeaveReason::ClientLeft, {}},
         out);  // during the handshake a Leave would be a protocol error: just close
  out.emplace_back(client_action::CloseDatagrams{});
  m_errorText = QStringLiteral("left the session");
  changeState(ClientState::Left, out);
  out.emplace_back(client_action::Disconnect{true});  // writes the Leave first
  return out;
}

void ClientEngine::onHostLeave(const Leave& leave, ClientActions& out) {
  out.emplace_back(client_action::CloseDatagrams{});
  m_leaveReason = leave.reason;
  m_errorText = leaveText(leave);
  changeState(ClientState::Left, out);
  out.emplace_back(client_action::Disconnect{false});
}

void ClientEngine::changeState(ClientState next, ClientActions& out) {
  if (next == m_state) return;
  m_state = next;
  if (next == ClientState::Left || next == ClientState::Failed) {  // nothing more will come
    m_deferredLevel.reset();
    m_wantedInFlight = false;
  }
  out.emplace_back(client_action::StateChanged{next});
}

void ClientEngine::send(const ControlMessage& message, ClientActions& out) {
  QByteArray frame = encodeControlMessage(message);
  if (!frame.isEmpty()) out.emplace_back(client_action::Send{std::move(frame)});
}

void ClientEngine::sendLock(const std::optional<LockMessage>& message, ClientActions& out) {
  if (message) send(*message, out);
}

// --- receiving

ClientActions ClientEngine::onMessage(const ControlDecodeResult& result, Micros now) {
  ClientActions out;
  if (m_state == ClientState::Handshaking) {
    handleHandshake(result.error == ControlError::None ? m_handshake.handleMessage(result.message)
                                                       : m_handshake.handleDecodeError(result.error),
                    out);
  } else if (!live()) {
    return out;
  } else if (result.error != ControlError::None) {
    fail(protocolError(QString::fromLatin1(toString(result.error))), out);
  } else {
    dispatch(result.message, now, out);
  }
  return out;
}

ClientActions ClientEngine::onPasswordKey(const QByteArray& key) {
  ClientActions out;
  if (m_state == ClientState::Handshaking) handleHandshake(m_handshake.keyDerived(key), out);
  return out;
}

void ClientEngine::handleHandshake(HandshakeOutput handshake, ClientActions& out) {
  for (const ControlMessage& message : handshake.send) send(message, out);
  if (handshake.deriveKey) out.emplace_back(client_action::DerivePasswordKey{std::move(*handshake.deriveKey)});
  if (m_handshake.state() == ClientHandshake::State::Refused) {
    fail(m_handshake.errorText(), out);
  } else if (m_handshake.state() == ClientHandshake::State::Joined && !m_session) {
    const Welcome& welcome = *m_handshake.session();
    if (const QString absurd = checkSessionShape(welcome.rowCount, welcome.vertexCount); !absurd.isEmpty()) {
      fail(protocolError(absurd), out);
      return;
    }
    m_session = welcome;
    m_lock = std::make_unique<LockClient>(m_session->peerId);
    out.emplace_back(client_action::OpenDatagrams{*m_session});
  }
}

void ClientEngine::dispatch(const ControlMessage& message, Micros now, ClientActions& out) {
  switch (messageType(message)) {
    case MessageType::ModelBegin:
      onModelBegin(std::get<ModelBegin>(message), out);
      return;
    case MessageType::ModelChunk:
      onModelChunk(std::get<ModelChunk>(message), out);
      return;
    case MessageType::Keyframe:
      onKeyframe(std::get<Keyframe>(message), out);
      return;
    case MessageType::PeerList:
      m_peers = std::get<PeerList>(message);
      out.emplace_back(client_action::Notify{ClientNotice::PeersChanged});
      return;
    case MessageType::LevelList:
      if (const QString absurd =
              checkLevelList(std::get<LevelList>(message), m_session->rowCount, m_session->vertexCount);
          !absurd.isEmpty()) {
        fail(protocolError(absurd), out);
        return;
      }
      m_levels = std::get<LevelList>(message);
      out.emplace_back(client_action::Notify{ClientNotice::LevelsChanged});
      return;
    case MessageType::LockNotice:
      sendLock(m_lock->apply(std::get<LockNotice>(message), toMillis(now)), out);
      out.emplace_back(client_action::Notify{ClientNotice::LockChanged});
      return;
    case MessageType::EditLog:
      m_editLog = std::get<EditLog>(message);
      out.emplace_back(client_action::Notify{ClientNotice::EditLogChanged});
      return;
    case MessageType::Presence:
      onPresence(std::get<Presence>(message), out);
      return;
    case MessageType::Heartbeat:
      return;
    case MessageType::Leave:
      onHostLeave(std::get<Leave>(message), out);
      return;
    default:
      fail(protocolError(QStringLiteral("unexpected message %1").arg(describe(messageType(message)))), out);
      return;
  }
}

// --- the user's commands

ClientActions ClientEngine::requestResolution(std::uint32_t wantedVertices) {
  ClientActions out;
  if (!live()) return out;
  if (m_deferredLevel) {  // the preview is still on its way: the newest choice replaces the deferred one
    m_deferredLevel = wantedVertices;
    out.emplace_back(client_action::Notify{ClientNotice::LevelChoiceKept});
    return out;
  }
  send(ResolutionRequest{wantedVertices}, out);
  return out;
}

ClientActions ClientEngine::requestLock(Micros now) { return lockCommand(&LockClient::request, now); }

ClientActions ClientEngine::releaseLock(Micros now) { return lockCommand(&LockClient::release, now); }

ClientActions ClientEngine::lockCommand(std::optional<LockMessage> (LockClient::*command)(Millis), Micros now) {
  ClientActions out;
  if (!live() || !m_lock) return out;
  const std::optional<LockMessage> message = ((*m_lock).*command)(toMillis(now));
  sendLock(message, out);
  if (message) out.emplace_back(client_action::Notify{ClientNotice::LockChanged});
  return out;
}

ClientActions ClientEngine::sendConstraints(std::vector<std::vector<std::uint32_t>> groups,
                                            std::vector<std::uint32_t> anchors) {
  ClientActions out;
  if (live() && m_lock && m_lock->canDrag()) {
    send(Constraints{m_lock->heldEpoch(), std::move(groups), std::move(anchors)}, out);  // none: breaks a limit
  }
  return out;
}

ClientActions ClientEngine::sendDrag(std::vector<HandleTransform> handles) {
  ClientActions out;
  if (live() && m_lock && m_lock->canDrag()) send(Drag{m_lock->heldEpoch(), std::move(handles)}, out);
  return out;
}

ClientActions ClientEngine::endStroke() {
  ClientActions out;
  if (live() && m_lock && m_lock->canDrag()) send(StrokeEnd{m_lock->heldEpoch()}, out);
  return out;
}

ClientActions ClientEngine::requestEdit(EditAction action) {
  ClientActions out;
  if (live()) send(EditRequest{action}, out);
  return out;
}

void ClientEngine::setDistortion(double maxPct, double meanPct, double lastPct) {
  m_hdMax = maxPct;
  m_hdMean = meanPct;
  m_hdLast = lastPct;
}

}  // namespace sc::session
