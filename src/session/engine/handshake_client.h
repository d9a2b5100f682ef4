#pragma once
// Client side of the connection handshake (docs/protocol.md, "Sequence"). A pure state machine: no sockets. The
// adapter sends what start() returns, feeds every decoded message (or the frame reader's errors) to
// handleMessage() / handleDecodeError(), sends what they return and closes when told to.
//
// States and transitions (entry side effects in changeState()):
//   SendHello               --start()-------------------------> AwaitChallengeOrWelcome (returns the Hello)
//   AwaitChallengeOrWelcome --Challenge, password known-------> DerivingKey (entry: output deriveKey, a
//                                                                 PasswordKeyRequest holding the password)
//   DerivingKey             --keyDerived(key)-----------------> AwaitWelcome (entry: send the ChallengeResponse)
//   AwaitChallengeOrWelcome --Challenge, < minIterations------> Refused (local: WeakChallenge; no proof is sent)
//   AwaitChallengeOrWelcome --Challenge, no password----------> Refused (local: PasswordRequired)
//   any non-final state but SendHello --Welcome---------------> Joined (session info stored)
//   any non-final state but SendHello --Refused---------------> Refused (host's reason and text stored)
//   any non-final state --any other message or decode error---> Refused (local: ProtocolError)
// Entering Refused sets `close` and sends nothing (the host sees the connection close). Joined and
// Refused are final: handleMessage() then returns nothing (after Welcome the session layer owns the messages).
//
// Contracts
//   - Network input is never asserted on. The password is used only to answer a Challenge and never sent.
//   - Challenge iterations are bounded by the decoder (1..kMaxPbkdf2Iterations), so answering costs at most
//     kMaxPbkdf2Iterations PBKDF2 rounds, made by the adapter off its thread (deriveKey, keyDerived()); and from
//     below by minIterations (kMinPbkdf2Iterations): an impostor host asking for fewer gets no proof to crack at
//     HMAC speed.

#include "session/engine/handshake_host.h"
#include "session/wire/control_messages.h"

#include <QtCore/QString>

#include <optional>

namespace sc::session {

struct ClientHandshakeConfig {
  QString displayName;              ///< ≤ kMaxNameBytes in UTF-8
  std::optional<QString> password;  ///< none: the user gave no password
  QByteArray channelBinding;        ///< SHA-256 of the certificate the host showed in the TLS handshake
  /// The fewest PBKDF2 iterations answered (password_auth.h); only tests whose hosts use fewer lower it.
  std::uint32_t minIterations = kMinPbkdf2Iterations;
};

/// Why the client ended in Refused.
enum class ClientFailure : std::uint8_t {
  None,
  RefusedByHost,     ///< the host sent Refused; see refusal()
  PasswordRequired,  ///< the host asked for a password and none was given
  ProtocolError,     ///< the host sent something unexpected or undecodable
  WeakChallenge,     ///< the host's Challenge asked for fewer PBKDF2 iterations than minIterations
};

class ClientHandshake {
 public:
  enum class State { SendHello, AwaitChallengeOrWelcome, DerivingKey, AwaitWelcome, Joined, Refused };

  explicit ClientHandshake(ClientHandshakeConfig config);

  /// The Hello to send first. Precondition: state() == SendHello.
  ControlMessage start();

  /// Single dispatcher for a decoded message from the host.
  HandshakeOutput handleMessage(const ControlMessage& message);

  /// The frame reader reported an error: local ProtocolError, close (nothing once final).
  HandshakeOutput handleDecodeError(ControlError error);

  /// The key asked for by deriveKey (derivePasswordKey of its password, salt and iterations): the ChallengeResponse
  /// to send. Ignored (nothing returned) unless state() == DerivingKey: the handshake may have ended meanwhile.
  HandshakeOutput keyDerived(const QByteArray& key);

  [[nodiscard]] State state() const { return m_state; }
  /// Session info from the host's Welcome; set exactly in state Joined.
  [[nodiscard]] const std::optional<Welcome>& session() const { return m_session; }
  /// The reason for Refused; None otherwise.
  [[nodiscard]] ClientFailure failure() const { return m_failure; }
  /// The host's Refused message when failure() == RefusedByHost.
  [[nodiscard]] const std::optional<Refused>& refusal() const { return m_refusal; }
  /// Readable reason for the UI: the host's text, or a local explanation; empty unless Refused.
  [[nodiscard]] const QString& errorText() const { return m_errorText; }
  /// Whether the password is still held: only until a Challenge is answered (then handed over in deriveKey).
  [[nodiscard]] bool holdsPassword() const { return m_config.password.has_value(); }

 private:
  HandshakeOutput handleChallenge(const Challenge& challenge);
  HandshakeOutput handleWelcome(const Welcome& welcome);
  HandshakeOutput handleRefused(const Refused& refused);
  HandshakeOutput fail(ClientFailure failure, const QString& text);
  /// The one place that changes m_state; performs the new state's entry side effects into `out`.
  void changeState(State next, HandshakeOutput& out);
  [[nodiscard]] bool running() const {
    return m_state == State::AwaitChallengeOrWelcome || m_state == State::DerivingKey || m_state == State::AwaitWelcome;
  }

  ClientHandshakeConfig m_config;
  State m_state = State::SendHello;
  std::optional<Challenge> m_challenge;
  std::optional<Welcome> m_session;
  std::optional<Refused> m_refusal;
  ClientFailure m_failure = ClientFailure::None;
  QString m_errorText;
};

}  // namespace sc::session
