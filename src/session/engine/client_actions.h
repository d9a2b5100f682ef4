#pragma once
// What the ClientEngine (client_engine.h) tells its adapter to do: an ordered list of actions, executed in order,
// one line each (SessionClient is the socket adapter; a second transport would be a second adapter). The actions
// carry the data the adapter needs; anything else it announces it reads back from the engine's accessors.
//
// Asynchronous requests and their answers (the adapter must report back):
//   Connect        → ClientEngine::onSecured(binding, now)   or onTransportError(text) / onClosed()
//   OpenDatagrams  → ClientEngine::onDatagramsOpened(now)    or fail("UDP bind failed: …")
//   StartDecode    → ClientEngine::onLevelDecoded(decodeLevel(job))   (decodeLevel() on a worker thread)
//   PublishFrame   → nothing: the adapter reads the displayed Z and frame number from its datagram channel.

#include "session/engine/client_level_decode.h"
#include "session/engine/handshake_host.h"
#include "session/wire/control_messages.h"

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <cstdint>
#include <variant>
#include <vector>

namespace sc::session {

/// The client's session states (docs/protocol.md, "Sequence"):
///   Idle → Connecting (TCP and TLS) → Handshaking (Hello …) → Loading (welcomed, no level yet) → Ready (a level is
///   displayed); any → Left (Leave either way) or Failed (refusal, error, silence). Left and Failed are final.
enum class ClientState : std::uint8_t { Idle, Connecting, Handshaking, Loading, Ready, Left, Failed };

/// Changes the adapter only announces (the data is in the engine's accessors).
enum class ClientNotice : std::uint8_t {
  PeersChanged,     ///< peers()
  LevelsChanged,    ///< levels()
  LockChanged,      ///< lock()
  LevelInstalled,   ///< displayLevel() is a new level (announced before its first PublishFrame)
  EditLogChanged,   ///< editLog()
  LevelChoiceKept,  ///< requestResolution() during a progressive join's preview: asked for once the preview is in
};

namespace client_action {

struct Connect {};  ///< open the control connection (TLS) toward the host
struct DerivePasswordKey {
  PasswordKeyRequest request;  ///< run derivePasswordKey off the adapter's thread and hand the key to onPasswordKey()
};
struct Send {
  QByteArray frame;  ///< one encoded control frame (encodeControlMessage), never empty
};
struct StateChanged {
  ClientState state;
};
struct OpenDatagrams {
  Welcome session;  ///< bind the datagram socket and open the path toward the host's udpPort with this key/token
};
struct CloseDatagrams {};  ///< stop the datagram path (its counters and Z stay readable)
struct Disconnect {
  bool flush = false;  ///< true: write what was sent first (our Leave), then close; false: abort
};
struct Failed {
  QString reason;  ///< also errorText()
};
struct Notify {
  ClientNotice notice;
};
struct ModelProgress {
  std::uint32_t received = 0;
  std::uint32_t total = 0;
};
struct SeedKeyframe {
  std::uint32_t frame = 0;
  Eigen::MatrixXd Z;  ///< m by 3, exact: seed the datagram channel with it and announce it (a Hausdorff reference)
};
struct StartDecode {
  LevelJob job;  ///< run decodeLevel(job) off the adapter's thread and hand the result to onLevelDecoded()
};
struct LevelFailed {
  QString reason;  ///< also levelError(); the previous level stays displayed
};
struct LevelReady {
  std::uint32_t vertexCount = 0;
};
struct PublishFrame {};
struct PresenceReceived {
  Presence presence;  ///< another member's (author ≥ 1, not us)
};                    ///< show the datagram channel's current Z and frame (coalesced: at most once per wake-up)

}  // namespace client_action

using ClientAction =
    std::variant<client_action::Connect, client_action::Send, client_action::StateChanged, client_action::OpenDatagrams,
                 client_action::CloseDatagrams, client_action::Disconnect, client_action::Failed, client_action::Notify,
                 client_action::ModelProgress, client_action::SeedKeyframe, client_action::StartDecode,
                 client_action::LevelFailed, client_action::LevelReady, client_action::PublishFrame,
                 client_action::PresenceReceived, client_action::DerivePasswordKey>;

/// In execution order. Empty from a user command (requestLock(), sendDrag(), …) means the command was refused.
using ClientActions = std::vector<ClientAction>;

}  // namespace sc::session
