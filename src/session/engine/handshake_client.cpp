#include "session/engine/handshake_client.h"

#include <cassert>

namespace sc::session {

ClientHandshake::ClientHandshake(ClientHandshakeConfig config) : m_config(std::move(config)) {}

ControlMessage ClientHandshake::start() {
  assert(m_state == State::SendHello && "start() once");
  HandshakeOutput unused;
  changeState(State::AwaitChallengeOrWelcome, unused);
  return Hello{kProtocolVersion, m_config.displayName};
}

HandshakeOutput ClientHandshake::handleMessage(const ControlMessage& message) {
  if (!running()) {
    // Before start() nothing may arrive; after a final state the session layer owns the messages.
    return m_state == State::SendHello ? fail(ClientFailure::ProtocolError, QStringLiteral("message before Hello"))
                                       : HandshakeOutput{};
  }
  const MessageType type = messageType(message);
  switch (type) {
    case MessageType::Challenge:
      if (m_state == State::AwaitChallengeOrWelcome) return handleChallenge(std::get<Challenge>(message));
      break;
    case MessageType::Welcome:
      return handleWelcome(std::get<Welcome>(message));
    case MessageType::Refused:
      return handleRefused(std::get<Refused>(message));
    default:
      break;
  }
  // The one error path: anything else, or a second Challenge.
  return fail(ClientFailure::ProtocolError,
              QStringLiteral("the host sent an unexpected message (0x%1) during the handshake")
                  .arg(static_cast<int>(type), 2, 16, QChar('0')));
}

HandshakeOutput ClientHandshake::handleDecodeError(ControlError error) {
  if (!running()) return {};
  return fail(ClientFailure::ProtocolError,
              QStringLiteral("the host sent an undecodable message (%1)").arg(QLatin1StringView(toString(error))));
}

HandshakeOutput ClientHandshake::handleChallenge(const Challenge& challenge) {
  if (!m_config.password) {
    return fail(ClientFailure::PasswordRequired, QStringLiteral("this session is protected by a password; "
                                                                "enter the password and join again"));
  }
  if (challenge.iterations < m_config.minIterations) {
    return fail(ClientFailure::WeakChallenge,
                QStringLiteral("the host asked for a password proof with only %1 PBKDF2 iterations (at least %2 are "
                               "required); it may be an impostor collecting passwords, so none was sent")
                    .arg(challenge.iterations)
                    .arg(m_config.minIterations));
  }
  m_challenge = challenge;
  HandshakeOutput out;
  changeState(State::DerivingKey, out);
  return out;
}

HandshakeOutput ClientHandshake::keyDerived(const QByteArray& key) {
  if (m_state != State::DerivingKey) return {};
  HandshakeOutput out;
  out.send.emplace_back(answerChallenge(key, *m_challenge, m_config.channelBinding));
  changeState(State::AwaitWelcome, out);
  return out;
}

HandshakeOutput ClientHandshake::handleWelcome(const Welcome& welcome) {
  m_session = welcome;
  HandshakeOutput out;
  changeState(State::Joined, out);
  return out;
}

HandshakeOutput ClientHandshake::handleRefused(const Refused& refused) {
  m_refusal = refused;
  m_failure = ClientFailure::RefusedByHost;
  m_errorText = refused.text;
  HandshakeOutput out;
  changeState(State::Refused, out);
  return out;
}

HandshakeOutput ClientHandshake::fail(ClientFailure failure, const QString& text) {
  m_failure = failure;
  m_errorText = text;
  HandshakeOutput out;
  changeState(State::Refused, out);
  return out;
}

void ClientHandshake::changeState(State next, HandshakeOutput& out) {
  m_state = next;
  switch (next) {
    case State::SendHello:
    case State::AwaitChallengeOrWelcome:
    case State::Joined:
      break;
    case State::AwaitWelcome:
      break;
    case State::DerivingKey:
      assert(m_challenge && m_config.password && "entered only on a Challenge with a password");
      // The request takes the password: the adapter overwrites and drops it once the key is made.
      out.deriveKey = PasswordKeyRequest{std::move(*m_config.password), m_challenge->salt, m_challenge->iterations};
      m_config.password.reset();
      break;
    case State::Refused:
      out.close = true;  // nothing is sent: the host sees the connection close
      break;
  }
}

}  // namespace sc::session
