#pragma once
// Typed control (TCP) messages and their codecs. Byte layouts: wire_format.h, "control messages"; sequence and
// rules: docs/protocol.md. Pure: no sockets, no clock.
//
// Contracts
//   - encodeControlMessage() returns one whole frame (length, type, body) or an empty array when the value breaks a
//     limit (name too long, bad peer id, non-finite float, …); it never asserts, so callers may pass user input.
//   - decodeControlMessage() checks every length before reading and every range after; a body that does not
//     decode exactly (short, trailing bytes, out of range, invalid UTF-8, non-finite) is Malformed. Whatever it
//     accepts re-encodes to a frame that decodes to an equal value.

#include "session/wire/lock_messages.h"
#include "session/wire/wire_format.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <array>
#include <cstdint>
#include <variant>
#include <vector>

namespace sc::session {

/// First message of a client. Only magic and version are read when the version differs from ours.
struct Hello {
  std::uint8_t version = kProtocolVersion;
  QString displayName;  ///< ≤ kMaxNameBytes in UTF-8
  friend bool operator==(const Hello&, const Hello&) = default;
};

/// Why the host refuses a client (wire values are explicit and stable).
enum class RefuseReason : std::uint8_t {
  VersionMismatch = 1,
  WrongPassword = 2,
  SessionFull = 3,
  ProtocolError = 4,  ///< malformed or unexpected message
  BadName = 5,
  ShuttingDown = 6,
};
inline constexpr std::uint8_t kRefuseReasonLast = 6;

struct Refused {
  RefuseReason reason = RefuseReason::ProtocolError;
  std::uint8_t hostVersion = kProtocolVersion;
  QString text;  ///< readable, ≤ kMaxTextBytes in UTF-8
  friend bool operator==(const Refused&, const Refused&) = default;
};

struct Challenge {
  QByteArray nonce;              ///< kNonceSize bytes, fresh per connection
  QByteArray salt;               ///< kSaltSize bytes, per session
  std::uint32_t iterations = 0;  ///< PBKDF2 count, 1..kMaxPbkdf2Iterations
  friend bool operator==(const Challenge&, const Challenge&) = default;
};

struct ChallengeResponse {
  QByteArray mac;  ///< kMacSize bytes, see password_auth.h
  friend bool operator==(const ChallengeResponse&, const ChallengeResponse&) = default;
};

struct Welcome {
  PeerId peerId = kNoPeer;        ///< 1..65535
  QByteArray datagramKey;         ///< kDatagramKeySize bytes
  QByteArray pathToken;           ///< kPathTokenSize bytes, echoed by the client over UDP to open the path
  std::uint16_t rowCount = 0;     ///< m, 1..kMaxRows
  std::uint32_t vertexCount = 0;  ///< full-resolution vertex count, ≥ 1
  std::uint16_t udpPort = 0;      ///< host's UDP port for PathOpen datagrams, ≥ 1
  friend bool operator==(const Welcome&, const Welcome&) = default;
};

enum class TransferKind : std::uint8_t { FullModel = 1, Level = 2 };

/// Announces a model transfer; its chunks follow. The receiver checks SHA-256 over the reassembled bytes.
struct ModelBegin {
  std::uint32_t transferId = 0;  ///< ≥ 1
  TransferKind kind = TransferKind::FullModel;
  std::uint32_t vertexCount = 0;  ///< ≥ 1
  std::uint32_t totalSize = 0;    ///< 1..kMaxTransferSize
  QByteArray sha256;              ///< kChecksumSize bytes
  friend bool operator==(const ModelBegin&, const ModelBegin&) = default;
};

struct ModelChunk {
  std::uint32_t transferId = 0;
  std::uint32_t offset = 0;
  std::uint32_t totalSize = 0;
  QByteArray bytes;  ///< 1..kMaxChunkBytes, offset + size ≤ totalSize
  friend bool operator==(const ModelChunk&, const ModelChunk&) = default;
};

struct ResolutionRequest {
  std::uint32_t vertexCount = 0;  ///< the host sends the level closest to this; 0 = full resolution
  friend bool operator==(const ResolutionRequest&, const ResolutionRequest&) = default;
};

struct PeerInfo {
  PeerId peerId = kNoPeer;  ///< 1..65535
  std::uint32_t vertexCount = 0;
  QString name;  ///< ≤ kMaxNameBytes in UTF-8
  friend bool operator==(const PeerInfo&, const PeerInfo&) = default;
};

struct PeerList {
  std::vector<PeerInfo> peers;  ///< ≤ kMaxPeers
  friend bool operator==(const PeerList&, const PeerList&) = default;
};

struct HandleTransform {
  std::uint16_t handle = 0;
  std::array<double, 12> affine{};  ///< 3×4 row-major [R | t], finite
  friend bool operator==(const HandleTransform&, const HandleTransform&) = default;
};

struct Drag {
  LockEpoch epoch = kNoEpoch;            ///< ≥ 1: the epoch of the lock the sender holds
  std::vector<HandleTransform> handles;  ///< ≤ kMaxHandles
  friend bool operator==(const Drag&, const Drag&) = default;
};

/// Exact (float64) coefficients of one frame: for a late joiner and as Hausdorff reference frames.
struct Keyframe {
  std::uint32_t frame = 0;
  std::vector<double> z;  ///< m×3 row-major (x, y, z per row), 1 ≤ m ≤ kMaxRows, finite
  friend bool operator==(const Keyframe&, const Keyframe&) = default;
};

/// Why a peer leaves (wire values explicit and stable; since version 4).
enum class LeaveReason : std::uint8_t {
  ClientLeft = 0,  ///< a client leaves of its own accord
  HostEnded = 1,   ///< the host ended the session (its user quit, left, or the host process was asked to stop)
  Kicked = 2,      ///< the host's user removed this client from the session
};
inline constexpr std::uint8_t kLeaveReasonLast = 2;

/// The last message before a graceful close, either direction.
struct Leave {
  LeaveReason reason = LeaveReason::ClientLeft;
  QString text;  ///< optional words for the other side, ≤ kMaxTextBytes in UTF-8 (plain text, never rich)
  friend bool operator==(const Leave&, const Leave&) = default;
};

struct Heartbeat {
  std::uint32_t sequence = 0;
  friend bool operator==(const Heartbeat&, const Heartbeat&) = default;
};

/// The lock holder's handle groups and anchors (vertex ids of the full-resolution mesh). Drags index the groups.
struct Constraints {
  LockEpoch epoch = kNoEpoch;                      ///< ≥ 1: the epoch of the lock the sender holds
  std::vector<std::vector<std::uint32_t>> groups;  ///< ≤ kMaxHandles groups, each non-empty
  std::vector<std::uint32_t> anchors;
  friend bool operator==(const Constraints&, const Constraints&) = default;
};

/// A client's receive figures (issue 4 item 6), sent to the host about once a second.
struct StatsReport {
  std::uint32_t vertexCount = 0;  ///< the displayed level's vertex count
  std::uint32_t framesApplied = 0;
  std::uint64_t received = 0;  ///< distinct datagrams
  std::uint64_t lost = 0;
  std::uint64_t late = 0;
  std::uint64_t dropped = 0;  ///< failed authentication or parsing
  double lossFraction = 0.0;  ///< all doubles finite and ≥ 0; loss and latency over the last 10 s (issue 16)
  double jitterMs = 0.0;
  double payloadKbpsIn = 0.0;
  double wireKbpsIn = 0.0;
  double framesPerSecond = 0.0;
  double latencyP50Ms = 0.0;
  double latencyP99Ms = 0.0;
  double hdMaxPct = 0.0;  ///< Hausdorff distortion, % of the bbox diagonal: max, mean, last over the references
  double hdMeanPct = 0.0;
  double hdLastPct = 0.0;
  friend bool operator==(const StatsReport&, const StatsReport&) = default;
};

/// One level of the host's resolution ladder, with exact figures (wire_format.h, LevelList).
struct LevelInfo {
  std::uint8_t levelId = 0;        ///< 0 = full model, i = i-th ladder level; < LevelList::total
  std::uint32_t vertexCount = 0;   ///< ≥ 1
  std::uint32_t faceCount = 0;     ///< ≥ 1
  std::uint32_t payloadBytes = 0;  ///< 1..kMaxTransferSize
  friend bool operator==(const LevelInfo&, const LevelInfo&) = default;
};

/// The levels the host has built so far, level ids strictly ascending (so the full model first when built).
struct LevelList {
  std::uint8_t total = 0;         ///< levels in the host's ladder (built or not), 1..kMaxLevels; 0 only unset
  std::vector<LevelInfo> levels;  ///< ≤ total, ids < total
  /// Every level of the ladder is listed (exact figures for all).
  [[nodiscard]] bool complete() const { return total > 0 && levels.size() == total; }
  friend bool operator==(const LevelList&, const LevelList&) = default;
};

/// One user's view of the session (issue 15: presence), ~30 per second while it changes, ~2 when idle. Client →
/// host with author 0 (the host overwrites it with the sender's id); host → every other member with the author's
/// id. Coordinates are the full-resolution model's (what the mesh file holds), finite, |value| ≤ kMaxPresenceCoord.
struct Presence {
  using Point = std::array<double, 3>;
  PeerId author = kNoPeer;  ///< 0 (client → host) or 1..65535
  Point eye{};              ///< camera position
  Point target{};           ///< the point the camera looks at
  Point up{};               ///< camera up vector (any length; drawing normalises it)
  bool pointerOn = false;   ///< the pointer is over the surface
  Point pointer{};          ///< its surface point; all zero when !pointerOn
  bool dragging = false;    ///< the user is dragging the handle
  bool handleOn = false;    ///< the user has painted a handle (since version 5)
  Point handle{};           ///< its centroid on the shape as shown; all zero when !handleOn
  friend bool operator==(const Presence&, const Presence&) = default;
};

/// The listed level whose vertex count is closest to `wanted` (ties: the larger); 0 = the largest (full). nullptr
/// when the list is empty. Cost: O(levels).
const LevelInfo* closestLevel(const LevelList& list, std::uint32_t wanted);

/// The lock holder's drag ended: what it changed becomes one step of the session's edit history, and its next
/// drag's poses start from the shape as it is now (docs/protocol.md, "Edits").
struct StrokeEnd {
  LockEpoch epoch = kNoEpoch;  ///< ≥ 1: the epoch of the lock the sender holds
  friend bool operator==(const StrokeEnd&, const StrokeEnd&) = default;
};

enum class EditAction : std::uint8_t {
  Undo = 1,  ///< undo the sender's latest applied step (the host's own user: anybody's)
  Redo = 2,  ///< redo the step the sender undid last
};

struct EditRequest {
  EditAction action = EditAction::Undo;
  friend bool operator==(const EditRequest&, const EditRequest&) = default;
};

/// One step of the session's edit history as the host lists it.
struct EditLogEntry {
  std::uint32_t step = 0;     ///< ≥ 1
  PeerId author = kNoPeer;    ///< kNoPeer: not in this session (restored from a saved session)
  PeerId undoneBy = kNoPeer;  ///< kNoPeer: applied
  bool redoable = false;      ///< undoneBy may redo it; false while applied
  QString authorName;         ///< ≤ kMaxNameBytes in UTF-8
  friend bool operator==(const EditLogEntry&, const EditLogEntry&) = default;
};

/// The latest steps of the session's edit history, oldest first (≤ kMaxEditLogSteps, ids strictly ascending).
struct EditLog {
  std::vector<EditLogEntry> steps;
  friend bool operator==(const EditLog&, const EditLog&) = default;
};

/// Any control message. LockMessage ↔ MessageType::LockRequest, LockNotice ↔ MessageType::LockNotice.
using ControlMessage =
    std::variant<Hello, Refused, Challenge, ChallengeResponse, Welcome, ModelBegin, ModelChunk, ResolutionRequest,
                 PeerList, LockMessage, LockNotice, Drag, Keyframe, Leave, Heartbeat, Constraints, StatsReport,
                 LevelList, StrokeEnd, EditRequest, EditLog, Presence>;

/// The wire type of a message value.
MessageType messageType(const ControlMessage& message);

/// One whole frame, or empty when `message` breaks a limit (see the contracts above). Cost: O(size).
QByteArray encodeControlMessage(const ControlMessage& message);

/// Why a frame was not delivered. `None` means a message was decoded.
enum class ControlError : std::uint8_t {
  None,
  Oversize,     ///< length field 0 or > kMaxControlMessageSize; the stream cannot be resynchronised
  UnknownType,  ///< type outside [kFirstControlType, ControlEnd)
  Malformed,    ///< body does not decode exactly
  Count,
};

/// Human-readable name of a ControlError ("oversize", …).
const char* toString(ControlError error);

struct ControlDecodeResult {
  ControlError error = ControlError::None;
  ControlMessage message;  ///< meaningful only when error == None
};

/// Decodes one body of the given wire type (the frame header already stripped). Never reads out of bounds.
ControlDecodeResult decodeControlMessage(std::uint8_t type, QByteArrayView body);

}  // namespace sc::session
