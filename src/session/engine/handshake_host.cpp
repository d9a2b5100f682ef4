#include "session/engine/handshake_host.h"

#include <QtCore/QList>

#include <cassert>

namespace sc::session {

SessionSecret makeSessionSecret(const QString& password, std::uint32_t iterations, const RandomBytes& random) {
  assert(iterations >= 1 && iterations <= kMaxPbkdf2Iterations && "PBKDF2 iterations out of range");
  SessionSecret secret;
  secret.salt = random(kSaltSize);
  secret.iterations = iterations;
  secret.key = derivePasswordKey(password, secret.salt, iterations);
  return secret;
}

bool isAcceptableDisplayName(const QString& name) {
  if (name.trimmed().isEmpty()) return false;
  for (const char32_t c : name.toUcs4()) {
    switch (QChar::category(c)) {
      case QChar::Other_Control:
      case QChar::Other_Format:
      case QChar::Other_Surrogate:
      case QChar::Other_PrivateUse:
      case QChar::Other_NotAssigned:
      case QChar::Separator_Line:
      case QChar::Separator_Paragraph:
        return false;
      default:
        break;
    }
    // Letters that render as nothing (Hangul fillers, the braille blank): a name could look like another.
    if (c == 0x115F || c == 0x1160 || c == 0x3164 || c == 0xFFA0 || c == 0x2800) return false;
  }
  return true;
}

HostHandshake::HostHandshake(HostHandshakeConfig config, Millis startedAt)
    : m_config(std::move(config)), m_startedAt(startedAt) {
  assert(m_config.random && "a random source is required");
  assert(m_config.peerId >= 1 && m_config.peerId <= 65535 && "peer ids are 16-bit and non-zero");
  assert(m_config.rowCount >= 1 && m_config.rowCount <= kMaxRows && "m out of range");
  assert(m_config.vertexCount >= 1 && "a model has vertices");
  assert(m_config.timeout.count() > 0 && "the timeout must be positive");
}

HandshakeOutput HostHandshake::handleMessage(const ControlMessage& message) {
  if (!running()) return {};  // final: the session layer (or nobody, when refused) owns the connection now
  const MessageType type = messageType(message);
  switch (type) {
    case MessageType::Hello:
      if (m_state == State::AwaitHello) return handleHello(std::get<Hello>(message));
      break;
    case MessageType::ChallengeResponse:
      if (m_state == State::AwaitResponse) return handleChallengeResponse(std::get<ChallengeResponse>(message));
      break;
    default:
      break;
  }
  // The one error path: anything else, or a message in the wrong state.
  return refuse(
      RefuseReason::ProtocolError,
      QStringLiteral("unexpected message 0x%1 during the handshake").arg(static_cast<int>(type), 2, 16, QChar('0')));
}

HandshakeOutput HostHandshake::handleDecodeError(ControlError error) {
  if (!running()) return {};
  return refuse(
      RefuseReason::ProtocolError,
      QStringLiteral("undecodable message during the handshake (%1)").arg(QLatin1StringView(toString(error))));
}

HandshakeOutput HostHandshake::tick(Millis now) {
  if (!running() || now - m_startedAt <= m_config.timeout) return {};
  return refuse(
      RefuseReason::ProtocolError,
      QStringLiteral("handshake timed out after %1 s").arg(static_cast<double>(m_config.timeout.count()) / 1000.0));
}

HandshakeOutput HostHandshake::handleHello(const Hello& hello) {
  if (hello.version != m_config.hostVersion) {
    return refuse(RefuseReason::VersionMismatch,
                  QStringLiteral("this host speaks ShapeCast protocol version %1, your client speaks version %2; "
                                 "both must run the same version")
                      .arg(m_config.hostVersion)
                      .arg(hello.version));
  }
  if (!isAcceptableDisplayName(hello.displayName)) {
    return refuse(RefuseReason::BadName, QStringLiteral("the display name must not be blank or contain control "
                                                        "characters"));
  }
  m_name = hello.displayName;
  if (!m_config.secret) return welcome();
  HandshakeOutput out;
  changeState(State::AwaitResponse, out);
  return out;
}

HandshakeOutput HostHandshake::welcome() {
  if (m_config.nameTaken && m_config.nameTaken(m_name)) {
    return refuse(RefuseReason::BadName, QStringLiteral("the name \"%1\" is already used in this session").arg(m_name));
  }
  if (m_config.sessionFull && m_config.sessionFull()) {
    return refuse(RefuseReason::SessionFull, QStringLiteral("the session is full"));
  }
  HandshakeOutput out;
  changeState(State::Welcomed, out);
  return out;
}

HandshakeOutput HostHandshake::handleChallengeResponse(const ChallengeResponse& response) {
  assert(m_config.secret && m_challenge && "AwaitResponse is entered only in password sessions");
  if (!verifyChallengeResponse(m_config.secret->key, *m_challenge, m_config.channelBinding, response)) {
    return refuse(RefuseReason::WrongPassword, QStringLiteral("wrong password"));
  }
  return welcome();
}

HandshakeOutput HostHandshake::refuse(RefuseReason reason, const QString& text) {
  m_refusal = Refused{reason, m_config.hostVersion, text};
  HandshakeOutput out;
  changeState(State::Refused, out);
  return out;
}

void HostHandshake::changeState(State next, HandshakeOutput& out) {
  m_state = next;
  switch (next) {
    case State::AwaitHello:
      break;
    case State::AwaitResponse:
      m_challenge = Challenge{m_config.random(kNonceSize), m_config.secret->salt, m_config.secret->iterations};
      out.send.emplace_back(*m_challenge);
      break;
    case State::Welcomed: {
      m_peer =
          NegotiatedPeer{m_config.peerId, m_name, m_config.random(kDatagramKeySize), m_config.random(kPathTokenSize)};
      out.send.emplace_back(Welcome{m_peer->peerId, m_peer->datagramKey, m_peer->pathToken, m_config.rowCount,
                                    m_config.vertexCount, m_config.udpPort});
      break;
    }
    case State::Refused:
      assert(m_refusal && "refuse() sets the reason first");
      out.send.emplace_back(*m_refusal);
      out.close = true;
      break;
  }
}

}  // namespace sc::session
