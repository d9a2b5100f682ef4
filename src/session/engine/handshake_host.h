#pragma once
// Host side of the connection handshake (docs/protocol.md, "Sequence"), one HostHandshake per incoming TCP
// connection. A pure state machine: no sockets, no timers. The adapter feeds it decoded control messages (or the
// ControlFrameReader's errors) and clock ticks (an injected monotonic `Millis`), sends what it returns and closes
// the connection when told to.
//
// States and transitions (entry side effects in changeState()):
//   AwaitHello    --Hello, version ≠ ours-------------> Refused  (VersionMismatch, text names both versions)
//   AwaitHello    --Hello, bad name--------------------> Refused  (BadName: blank, control or invisible characters)
//   AwaitHello    --Hello, password session-----------> AwaitResponse (entry: send Challenge, fresh nonce)
//   AwaitHello    --Hello, open session, name taken / full--> Refused (BadName | SessionFull)
//   AwaitHello    --Hello, open session---------------> Welcomed (entry: send Welcome, fresh key and token)
//   AwaitResponse --ChallengeResponse, right MAC, name taken / full--> Refused (BadName | SessionFull)
//   AwaitResponse --ChallengeResponse, right MAC------> Welcomed
//   AwaitResponse --ChallengeResponse, wrong MAC------> Refused  (WrongPassword)
//   AwaitHello | AwaitResponse --any other message or a decode error--> Refused (ProtocolError)
//   AwaitHello | AwaitResponse --tick() strictly after start + timeout--> Refused (ProtocolError, "timed out")
// Entering Refused sends one Refused message and sets `close`. Welcomed and Refused are final: handleMessage()
// and tick() then return nothing (after Welcome the session layer owns the connection's messages).
//
// Contracts
//   - Network input is never asserted on (style.md item 6); the configuration is trusted and asserted on.
//   - All randomness (nonce, datagram key, path token) comes from the injected RandomBytes, so tests are
//     deterministic; production passes secureRandomBytes.
//   - The host keeps only the PBKDF2 key of the password (SessionSecret), derived once per session.
//   - A stranger learns nothing of the session before its password proof: whether a name is taken and whether the
//     session is full are asked (nameTaken, sessionFull) only once the proof is right, just before the Welcome, so
//     seats are counted after authentication.
// Cost: O(1) per message plus one HMAC for a ChallengeResponse; no PBKDF2 per connection.

#include "session/wire/control_messages.h"
#include "session/wire/password_auth.h"

#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <functional>
#include <optional>
#include <vector>

namespace sc::session {

/// Source of random bytes: returns exactly `count` bytes.
using RandomBytes = std::function<QByteArray(int count)>;

/// A password key to derive (derivePasswordKey: PBKDF2, O(iterations), up to a second at kMaxPbkdf2Iterations) off
/// the adapter's thread and hand back with ClientHandshake::keyDerived(). Holds the client's only copy of the
/// password from then on: overwrite and drop it once the key is made.
struct PasswordKeyRequest {
  QString password;
  QByteArray salt;
  std::uint32_t iterations = 0;
};

/// What a handshake step asks the adapter to do: send `send` in order, then close the connection if `close`; the
/// client's, on a Challenge it answers, also derive `deriveKey`.
struct HandshakeOutput {
  std::vector<ControlMessage> send;
  bool close = false;
  std::optional<PasswordKeyRequest> deriveKey;
};

/// What the host keeps of a session password: PBKDF2 key with its salt and iteration count, never the password.
struct SessionSecret {
  QByteArray salt;                                      ///< kSaltSize bytes
  std::uint32_t iterations = kDefaultPbkdf2Iterations;  ///< 1..kMaxPbkdf2Iterations
  QByteArray key;                                       ///< kMacSize bytes
};

/// Derives the session secret once: random salt from `random`, PBKDF2 with `iterations` (≥ 1). Cost: O(iterations).
SessionSecret makeSessionSecret(const QString& password, std::uint32_t iterations, const RandomBytes& random);

/// True for a display name the host accepts: not blank after trimming, no control, format (zero-width, bidi),
/// private-use, unassigned or line/paragraph separator characters and no invisible filler letters (length is the
/// decoder's check: ≤ kMaxNameBytes).
bool isAcceptableDisplayName(const QString& name);

inline constexpr Millis kHandshakeTimeout{10000};  ///< a connection not welcomed by then is refused and closed

struct HostHandshakeConfig {
  std::optional<SessionSecret> secret;            ///< none: open session, no Challenge
  std::function<bool()> sessionFull;              ///< optional, asked after the proof: true refuses (SessionFull)
  std::function<bool(const QString&)> nameTaken;  ///< optional, asked after the proof: true refuses (BadName)
  std::uint8_t hostVersion = kProtocolVersion;
  std::uint16_t rowCount = 1;     ///< m, 1..kMaxRows
  std::uint32_t vertexCount = 1;  ///< full-resolution vertex count, ≥ 1
  std::uint16_t udpPort = 1;      ///< the host's UDP port, ≥ 1 (sent in the Welcome)
  PeerId peerId = kNoPeer;        ///< id to assign, 1..65535
  RandomBytes random;             ///< required
  Millis timeout = kHandshakeTimeout;
  QByteArray channelBinding;  ///< SHA-256 of the host's TLS certificate, mixed into the password proof
};

/// The joined peer, available once Welcomed.
struct NegotiatedPeer {
  PeerId peerId = kNoPeer;
  QString name;
  QByteArray datagramKey;  ///< kDatagramKeySize bytes
  QByteArray pathToken;    ///< kPathTokenSize bytes
  friend bool operator==(const NegotiatedPeer&, const NegotiatedPeer&) = default;
};

class HostHandshake {
 public:
  enum class State { AwaitHello, AwaitResponse, Welcomed, Refused };

  /// `startedAt`: when the connection was accepted (the timeout counts from here).
  HostHandshake(HostHandshakeConfig config, Millis startedAt);

  /// Single dispatcher for a decoded message from the client.
  HandshakeOutput handleMessage(const ControlMessage& message);

  /// The frame reader reported an error (Oversize, UnknownType, Malformed): Refused(ProtocolError) and close
  /// while the handshake runs; nothing once final (the session layer applies its own rule).
  HandshakeOutput handleDecodeError(ControlError error);

  /// Refuses and closes when the handshake has run strictly longer than the timeout. Call often.
  HandshakeOutput tick(Millis now);

  [[nodiscard]] State state() const { return m_state; }
  /// The joined peer; set exactly in state Welcomed.
  [[nodiscard]] const std::optional<NegotiatedPeer>& peer() const { return m_peer; }
  /// Why the client was refused; set exactly in state Refused.
  [[nodiscard]] const std::optional<Refused>& refusal() const { return m_refusal; }

 private:
  HandshakeOutput handleHello(const Hello& hello);
  HandshakeOutput handleChallengeResponse(const ChallengeResponse& response);
  /// After the proof (or the Hello of an open session): the name and seat checks, then Welcomed or Refused.
  HandshakeOutput welcome();
  HandshakeOutput refuse(RefuseReason reason, const QString& text);
  /// The one place that changes m_state; performs the new state's entry side effects into `out`.
  void changeState(State next, HandshakeOutput& out);
  [[nodiscard]] bool running() const { return m_state == State::AwaitHello || m_state == State::AwaitResponse; }

  HostHandshakeConfig m_config;
  Millis m_startedAt;
  State m_state = State::AwaitHello;
  QString m_name;
  std::optional<Challenge> m_challenge;
  std::optional<NegotiatedPeer> m_peer;
  std::optional<Refused> m_refusal;
};

}  // namespace sc::session
