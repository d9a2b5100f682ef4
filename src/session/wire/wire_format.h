#pragma once
// THE wire format of ShapeCast (style.md item 10): every byte that crosses the network is described here.
//
// Conventions
//   - Fixed-width integers only. All multi-byte fields are BIG-endian (network order), converted once, here, by
//     encodeDatagramHeader()/decodeDatagramHeader() through qToBigEndian/qFromBigEndian.
//   - Every decoder checks the length before reading a field; malformed input is dropped and counted by the caller
//     (style.md item 6), never asserted on.
//
// ==================================================================================================================
// Coefficient datagram (UDP, host -> client), MessageType::CoefficientFrame; encrypted since version 3
// ==================================================================================================================
// One frame's m×3 displacement coefficients Z are sent as P datagrams ("parts"). Rows 0..p−1 (the protected low
// frequencies) are repeated in every part; the other rows are interleaved: part j carries rows k ≥ p with
// (k − p) mod P == j, in ascending order. Values are int16 with one power-of-two step per band of `bandRows` rows.
//
//  offset size field            meaning
//  ------ ---- ---------------- ---------------------------------------------------------------------------------
//     0    2   magic            0x5343 ("SC")
//     2    1   version          kProtocolVersion
//     3    1   type             MessageType (CoefficientFrame)
//     4    2   peerId           receiving peer's id (selects the per-client key on the host side)
//     6    2   sequence         low 16 bits of the per-peer 64-bit extended sequence number S (+1 per datagram,
//                               never wraps; the receiver extends the 16 bits to the S closest to its newest,
//                               ReplayWindow::extend, and the tag covers the whole S)
//     8    4   frame            frame number, +1 per frame (serial-number arithmetic, wraps)
//    12    1   partIndex        j in [0, partCount)
//    13    1   partCount        P in [1, kMaxParts]
//    14    2   rowCount         m in [1, kMaxRows]: rows in the whole frame
//    16    1   protectedRows    p in [0, m]
//    17    1   bandRows         rows per band, ≥ 1; band b covers rows [b·bandRows, (b+1)·bandRows)
//    18    4   timestamp        host's monotonic clock in µs, mod 2³², when the input that produced this frame
//                               arrived (the drag command; the send time for refresh frames). Receivers use
//                               differences only (RTP-style jitter), or, on one machine, one-way latency.
//  ------ ---- ---------------- --------------------------------------------- 22 bytes: kDatagramHeaderSize
//    22    B   bandExponent[B]  int8 e_b per band, B = ceil(m / bandRows); value = q · 2^e_b
//   22+B  6·p  protected        p rows × (x, y, z) int16
//   ...   6·r  interleaved      r = number of k in [p, m) with (k − p) mod P == j, rows × (x, y, z) int16
//   end−T  T   tag              AES-128-GCM tag (T = kTagSize = 16 bytes). Bytes 22..end−T (exponents and rows)
//                               are AES-128-GCM ciphertext; the 22-byte header is additional authenticated data
//                               (clear). Key: HKDF-SHA256(perClientKey, info "ShapeCast v3 datagram host->client"),
//                               16 bytes; nonce: u32 BE 1 (host → client) ‖ u64 BE S (datagram_cipher.h). S is not
//                               sent: a datagram of an earlier 16-bit cycle replayed later extends to another S
//                               and fails the tag.
//
// Sizes for m = 100, p = 10, bandRows = 10, P = 2: 22 + 10 + 60 + 45·6 + 16 = 378 bytes per part, 756 per frame.
//
// Receiver order of checks: length ≥ kDatagramMinSize (Truncated), extend the sequence, decrypt + tag (BadTag), magic
// (BadMagic), version
// (BadVersion), type and field ranges (Malformed), exact length (Truncated/Malformed), then the replay window
// (Replayed/Stale), which is updated only after everything else succeeded (RFC 6347 §4.1.2.6).
//
// ==================================================================================================================
// Path-open datagram (UDP, client -> host), MessageType::PathOpen: opens (and keeps open, through NATs) the path
// the host sends coefficient datagrams on. The host answers at most a PathChallenge (below) to a new address; it
// records the datagram's source address as the client's candidate UDP address. Sent after the Welcome every 500 ms
// until the first coefficient datagram arrives, then every kPathRefreshMs. 42 bytes:
//
//  offset size field      meaning
//     0    2   magic      0x5343
//     2    1   version    kProtocolVersion
//     3    1   type       MessageType::PathOpen
//     4    2   peerId     the client's id from the Welcome (selects the key on the host)
//     6   16   token      pathToken from the Welcome
//    22    4   sequence   u32: 1 for the first PathOpen after a Welcome, +1 for every one sent (never wraps)
//    26   16   tag        HMAC-SHA256(datagramKey, bytes 0..25), truncated
//
// Host order of checks: exact length (Truncated), peerId known (Stranger), tag (BadTag), magic/version/type
// (Malformed), token (Stranger), sequence > the highest accepted from that peer since its Welcome (Replayed).
// Every drop is counted. Only an accepted PathOpen raises the highest sequence; since version 3 it does not move
// the path by itself: its source address and port become the peer's *candidate* path, which must prove that it
// receives (below) before any coefficient datagram goes there.
//
// ==================================================================================================================
// Path challenge and response (UDP; since version 3): validation of a candidate path, as QUIC's PATH_CHALLENGE /
// PATH_RESPONSE (RFC 9000 §8.2). For each accepted PathOpen from a candidate address the host sends that address a
// PathChallenge carrying a random u64 (new per candidate, repeated while the same candidate keeps sending), but only
// while the bytes it sent there stay ≤ the bytes of accepted PathOpens it received from there (no amplification:
// 30 ≤ 42). The client answers each authentic PathChallenge with a PathResponse carrying the same value, to the
// host's address. A PathResponse from the candidate address and port with the candidate's value validates the
// path: from then on the coefficient datagrams go there. Until then they keep going to the old validated path (or
// nowhere, before the first). 30 bytes, both types:
//
//  offset size field      meaning
//     0    2   magic      0x5343
//     2    1   version    kProtocolVersion
//     3    1   type       MessageType::PathChallenge (host → client) or PathResponse (client → host)
//     4    2   peerId     the client's id (selects the key)
//    6     8   challenge  u64, random (host's CSPRNG), echoed unchanged
//    14   16   tag        HMAC-SHA256(datagramKey, bytes 0..13), truncated
//
// Order of checks on both ends: exact length and type byte (else not a probe), peerId (Stranger), tag (BadTag),
// magic/version (Malformed); the host then needs a candidate path of that peer with the datagram's source address,
// port and value (else WrongChallenge). Nothing else is ever answered.
//
// ==================================================================================================================
// Control messages (TCP, both directions), MessageType 0x40..0x55. Typed values and codecs: control_messages.h;
// the handshake sequence and the rules: docs/protocol.md.
// ==================================================================================================================
// A TCP connection carries a stream of frames. The frame header and the type values of Hello (0x40) and Refused
// (0x41) are frozen for every protocol version, so that a peer of any version can be refused with a reason.
//
//  offset size field   meaning
//  ------ ---- ------- ---------------------------------------------------------------------------------------------
//     0    4   length  L = 1 + body size, 1 ≤ L ≤ kMaxControlMessageSize; anything else ends the connection
//     4    1   type    MessageType, kFirstControlType ≤ type < ControlEnd
//     5   L−1  body    per type, below; the body must be consumed exactly (trailing bytes = malformed)
//
// Byte order is converted by byte_io.h (ByteWriter/ByteReader). Text is UTF-8 (validated on decode) with a
// length prefix; "b[n]" is n raw bytes; f64 is an IEEE-754 binary64, big-endian, and must be finite. Peer ids are
// in [1, 65535] (the datagram header field is 16 bits).
//
// 0x40 Hello (client → host, first message)          | 0x41 Refused (host → client, then the host closes)
//    0  2  magic    0x5343                            |    0  1  reason   RefuseReason (1..6)
//    2  1  version  client's kProtocolVersion; a host |    1  1  version  host's kProtocolVersion
//               with another version refuses without  |    2  2  textLen  t ≤ kMaxTextBytes
//               reading further (Hello may grow)      |    4  t  text     readable reason, UTF-8
//    3  1  nameLen  n ≤ kMaxNameBytes                 |
//    4  n  name     display name, UTF-8               |
//
// 0x42 Challenge (host → client, password sessions)  | 0x43 ChallengeResponse (client → host)
//    0 32  nonce       fresh random per connection    |    0 32  mac  HMAC-SHA256(PBKDF2-HMAC-SHA256(password,
//   32 16  salt        per-session random salt        |               salt, iterations, 32), "SC-auth1" ‖ nonce)
//   48  4  iterations  PBKDF2 count, 1..kMaxPbkdf2Iterations
//
// 0x44 Welcome (host → client)                       | 0x45 ModelBegin (host → client, before a transfer's chunks)
//    0  4  peerId       the client's id, 1..65535     |    0  4  transferId   ≥ 1, new per transfer
//    4 32  datagramKey  per-client HMAC key (UDP)     |    4  1  kind         1 FullModel, 2 Level
//   36 16  pathToken    sent by the client over UDP   |    5  4  vertexCount  of the mesh transferred, ≥ 1
//   52  2  rowCount     m, 1..kMaxRows                |    9  4  totalSize    bytes, 1..kMaxTransferSize
//   54  4  vertexCount  full-resolution mesh, ≥ 1     |   13 32  sha256       SHA-256 of all totalSize bytes
//   58  2  udpPort      host's UDP port (≥ 1) for     |
//                       PathOpen datagrams            |
//
// 0x46 ModelChunk (host → client)                    | 0x47 ResolutionRequest (client → host)
//    0  4  transferId  as in its ModelBegin           |    0  4  vertexCount  wanted level (closest); 0 = full
//    4  4  offset      of the first byte              |
//    8  4  totalSize   as in its ModelBegin           | 0x49 LockRequest (client → host; lock_messages.h)
//   12  4  n           1..kMaxChunkBytes, offset + n  |    0  1  kind   LockRequestKind 1 Request 2 Release 3 Renew
//                      ≤ totalSize                    |    1  4  epoch  LockEpoch (0 = none)
//   16  n  bytes                                      |
//
// 0x48 PeerList (host → all, on every change)        | 0x4a LockNotice (host → peer(s); lock_messages.h)
//    0  2  count  c ≤ kMaxPeers, then c entries:      |    0  1  kind      LockNoticeKind 1..6 (v4: 5 Waiting;
//                                                     |                    v5: 6 Refused)
//          +0  4  peerId       1..65535               |    1  4  peer      PeerId
//          +4  4  vertexCount  its resolution level   |    5  4  epoch     LockEpoch
//          +8  1  nameLen      n ≤ kMaxNameBytes      |    9  4  queuePos  Queued: 1 = next, else 0
//          +9  n  name         UTF-8                  |   13  1  reason    LockReleaseReason 0..3 (v4: 3
//                                                     |                    RevokedByHost)
//                                                     |   14  1  count     w ≤ kMaxPeers; 0 unless Waiting (v4)
//                                                     |                    or Refused (v5)
//                                                     |   15 4w  waiting   PeerIds 1..65535: Waiting the queue,
//                                                     |                    head first; Refused the holders the
//                                                     |                    set overlaps
//
// 0x4b Drag (lock holder → host)                     | 0x4c Keyframe (host → client: at join, exact references)
//    0  4  epoch  the held lock's epoch, ≥ 1          |    0  4  frame     frame number of these coefficients
//    4  2  count  h ≤ kMaxHandles, then h entries:    |    4  2  rowCount  m, 1..kMaxRows
//          +0  2  handle     handle index             |    6 24m Z         m rows × (x, y, z) f64, row-major:
//          +2 96  transform  3×4 affine f64, row-major|                    full precision, not quantised
//
// 0x4d Leave (either direction, then close; v4)     | 0x4e Heartbeat (either direction, ~1 s): 0 4 sequence
//    0  1  reason   LeaveReason 0 ClientLeft,         |
//                   1 HostEnded, 2 Kicked             |
//    1  2  textLen  t ≤ kMaxTextBytes                 |
//    3  t  text     optional words, UTF-8, plain      |
//
// 0x4f Constraints (lock holder → host, before drags)| 0x50 StatsReport (client → host, ~1 s)
//    0  4  epoch   the held lock's epoch, ≥ 1         |    0  4  vertexCount      displayed level's vertices
//    4  2  groups  g ≤ kMaxHandles, then g entries:   |    4  4  framesApplied    since join
//          +0  4  count  c ≥ 1                        |    8  8  received         distinct datagrams (u64)
//          +4 4c  vertex ids, u32, < vertexCount      |   16  8  lost             cumulative (u64)
//    …  4  anchors  a, then a × u32 vertex ids        |   24  8  late             (u64)
//    Σ ids ≤ kMaxConstraintVertices; drags index the  |   32  8  dropped          failed auth/parse (u64)
//    groups in this order                             |   40 80  10 × f64: lossFraction (last 10 s), jitterMs, kbpsIn
//                                                     |          (payload), wireKbpsIn, framesPerSecond,
//                                                     |          latencyP50Ms, latencyP99Ms (last 10 s), hdMaxPct,
//                                                     |          hdMeanPct, hdLastPct (finite, ≥ 0)
//
// 0x51 LevelList (host → client: after the Welcome, then again whenever it changes)
//    0  1  total  levels in the host's ladder, full model included, 1..kMaxLevels (built or not)
//    1  1  count  c ≤ total: levels built so far, then c entries of kLevelEntrySize = 13 bytes, ids ascending:
//          +0  1  levelId       0 = the full model, i = the i-th ladder level (50%, 20%, 5% of n: 1, 2, 3)
//          +1  4  vertexCount   exact vertex count n' of that level, ≥ 1 (what a transfer of it will carry)
//          +5  4  faceCount     exact face count, ≥ 1
//          +9  4  payloadBytes  size of its transfer (ModelBegin.totalSize), 1..kMaxTransferSize
//    Lists the levels the host has built so far (it builds the whole ladder in the background after the first
//    Welcome; count == total: complete); a ResolutionRequest for a listed vertexCount gets exactly that level.
//
// 0x52 StrokeEnd (lock holder → host: the drag that  | 0x53 EditRequest (member → host)
//      was going on ended; it becomes an edit step)  |    0  1  action  1 = undo my latest step (the host's own
//    0  4  epoch  the held lock's epoch, ≥ 1          |                    user: anybody's), 2 = redo what I undid
//
// 0x54 EditLog (host → all: after every change of the session's edit history, and to a newcomer)
//    0  1  count  c ≤ kMaxEditLogSteps: the latest steps, then c entries, step ids strictly ascending:
//          +0  4  step      ≥ 1, the step's id in this session
//          +4  4  author    its author's PeerId; 0 = not in this session (restored from a saved session)
//          +8  4  undoneBy  who undid it (PeerId), 0 = applied
//          +12 1  redoable  1 = undoneBy may redo it (0 once undoneBy committed a newer step), 0 when applied
//          +13 1  nameLen   n ≤ kMaxNameBytes, then n bytes: the author's name, UTF-8
//
// 0x55 Presence (client → host, host → the other members; since version 4), kPresenceSize = 125 bytes (v5; 101 in v4):
//    0  4  author   0 from a client (the host overwrites it with the sender's id); the author's id 1..65535 from
//                   the host
//    4  1  flags    bit 0: pointer on the surface, bit 1: dragging, bit 2: handle painted (v5); other bits 0
//    5 24  eye      3 × f64, camera position, full-resolution model coordinates
//   29 24  target   3 × f64, the point the camera looks at
//   53 24  up       3 × f64, camera up vector
//   77 24  pointer  3 × f64, the pointer's surface point; all 0 when bit 0 is clear
//  101 24  handle   3 × f64, the centroid of the user's handle as shown (v5); all 0 when bit 2 is clear
//    Every f64 finite with |value| ≤ kMaxPresenceCoord. The host relays at most presenceRate per peer (excess
//    dropped and counted, never a close by itself); senders send ≤ 30/s while moving, ≤ 2/s when idle.
//
// ==================================================================================================================

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <optional>

namespace sc::session {

inline constexpr std::uint16_t kMagic = 0x5343;  ///< "SC", first two bytes of every datagram.
/// 3: issue 14 (encrypted datagrams, path challenge); 4: issue 15 (strokes and the shared edit history, presence,
/// Leave reason and text, LockNotice Waiting with the lock queue, Released{RevokedByHost}); 5: several leases at
/// once (one Granted per lease to a newcomer, LockNotice Refused for overlapping constraints); 6: issue 17 (level
/// payloads in level format 2: K as int16 with a float scale per column, spectral/quantized_basis.h).
inline constexpr std::uint8_t kProtocolVersion = 6;

/// Message types, explicit values. Datagram types use values below 0x40, control (TCP) types from 0x40 on.
enum class MessageType : std::uint8_t {
  CoefficientFrame = 0x01,
  PathOpen = 0x02,
  PathChallenge = 0x03,  ///< host → client: prove that this address receives (since version 3)
  PathResponse = 0x04,   ///< client → host: the challenge echoed back
  Count,                 ///< one past the last datagram type; keep last among datagram types.
  // Control (TCP) messages; layouts in the "control messages" section. Hello and Refused are frozen forever.
  Hello = 0x40,
  Refused = 0x41,
  Challenge = 0x42,
  ChallengeResponse = 0x43,
  Welcome = 0x44,
  ModelBegin = 0x45,
  ModelChunk = 0x46,
  ResolutionRequest = 0x47,
  PeerList = 0x48,
  LockRequest = 0x49,
  LockNotice = 0x4a,
  Drag = 0x4b,
  Keyframe = 0x4c,
  Leave = 0x4d,
  Heartbeat = 0x4e,
  Constraints = 0x4f,
  StatsReport = 0x50,
  LevelList = 0x51,
  StrokeEnd = 0x52,    ///< since version 4
  EditRequest = 0x53,  ///< since version 4
  EditLog = 0x54,      ///< since version 4
  Presence = 0x55,     ///< cameras, pointers, dragging (since version 4)
  ControlEnd,          ///< one past the last control type; keep last.
};
inline constexpr std::uint8_t kMessageTypeMask = 0x7f;  ///< the high bit is reserved (must be 0).
inline constexpr std::uint8_t kFirstControlType = 0x40;
static_assert(static_cast<std::uint8_t>(MessageType::Count) <= kFirstControlType);
static_assert(static_cast<std::uint8_t>(MessageType::ControlEnd) - 1 <= kMessageTypeMask);

// === size table
inline constexpr int kDatagramHeaderSize = 22;  ///< fixed header, offsets 0..21.
inline constexpr int kTagSize = 16;             ///< AES-GCM tag (coefficients), truncated HMAC-SHA256 (path).
inline constexpr int kDatagramMinSize = kDatagramHeaderSize + kTagSize;
inline constexpr int kMaxDatagramSize = 1200;  ///< QUIC's floor; every datagram we send is at most this.
inline constexpr int kValueSize = 2;           ///< one int16 coefficient.
inline constexpr int kRowSize = 3 * kValueSize;
inline constexpr int kMaxParts = 64;
inline constexpr int kMaxRows = 4096;
// control messages
inline constexpr int kControlLengthSize = 4;                     ///< the u32 length field.
inline constexpr int kControlHeaderSize = 5;                     ///< length + type.
inline constexpr std::uint32_t kMaxControlMessageSize = 131072;  ///< largest L (type + body): 128 KiB.
inline constexpr int kMaxNameBytes = 64;                         ///< display name, UTF-8 bytes.
inline constexpr int kMaxTextBytes = 512;                        ///< refusal text, UTF-8 bytes.
inline constexpr int kNonceSize = 32;
inline constexpr int kSaltSize = 16;
inline constexpr int kMacSize = 32;  ///< HMAC-SHA256, untruncated.
inline constexpr std::uint32_t kMaxPbkdf2Iterations = 1000000;
inline constexpr int kDatagramKeySize = 32;
inline constexpr int kPathTokenSize = 16;
inline constexpr int kChecksumSize = 32;  ///< SHA-256.
inline constexpr std::uint32_t kMaxChunkBytes = 65536;
inline constexpr std::uint32_t kMaxTransferSize = 1u << 30;  ///< 1 GiB per model transfer.
inline constexpr int kMaxPeers = 128;
inline constexpr int kMaxLevels = 16;       ///< LevelList: levels in a ladder
inline constexpr int kLevelEntrySize = 13;  ///< one LevelList entry
inline constexpr int kMaxHandles = 64;
inline constexpr int kPeerEntryMinSize = 9;  ///< PeerList entry without its name.
inline constexpr int kHandleEntrySize = 2 + 12 * 8;
inline constexpr int kPathOpenSize = 10 + kPathTokenSize + kTagSize;           ///< 42 bytes
inline constexpr int kPathChallengeValueSize = 8;                              ///< random u64 of a path challenge
inline constexpr int kPathProbeSize = 6 + kPathChallengeValueSize + kTagSize;  ///< 30 bytes, ≤ kPathOpenSize
static_assert(kPathProbeSize <= kPathOpenSize, "a challenge must not send more than the PathOpen that caused it");
inline constexpr int kPathRefreshMs = 5000;  ///< path-open refresh once frames flow (NAT bindings last ≥ 30 s)
inline constexpr std::uint32_t kMaxConstraintVertices = 30000;  ///< handle + anchor ids in one Constraints
inline constexpr int kMaxEditLogSteps = 64;  ///< EditLog: the latest steps of the session's edit history
inline constexpr int kStatsReportSize = 40 + 10 * 8;
inline constexpr int kPresenceSize = 4 + 1 + 15 * 8;  ///< 125 bytes
inline constexpr double kMaxPresenceCoord = 1e9;      ///< Presence coordinates: |value| ≤ this
static_assert(1 + 6 + 24 * kMaxRows <= static_cast<int>(kMaxControlMessageSize));              // largest Keyframe
static_assert(1 + 16 + kMaxChunkBytes <= kMaxControlMessageSize);                              // largest ModelChunk
static_assert(1 + 10 + 4 * (kMaxHandles + kMaxConstraintVertices) <= kMaxControlMessageSize);  // largest Constraints

/// The fixed header of a coefficient datagram, host byte order.
struct DatagramHeader {
  std::uint16_t magic = kMagic;
  std::uint8_t version = kProtocolVersion;
  MessageType type = MessageType::CoefficientFrame;
  std::uint16_t peerId = 0;
  std::uint16_t sequence = 0;
  std::uint32_t frame = 0;
  std::uint8_t partIndex = 0;
  std::uint8_t partCount = 1;
  std::uint16_t rowCount = 0;
  std::uint8_t protectedRows = 0;
  std::uint8_t bandRows = 1;
  std::uint32_t timestamp = 0;  ///< host clock, µs mod 2³² (see the table)
};

/// Appends the 22 header bytes, big-endian, to `out`. Cost: O(1).
void encodeDatagramHeader(const DatagramHeader& header, QByteArray& out);

/// Reads the 22 header bytes at the start of `bytes`; std::nullopt when fewer than 22 bytes. Checks nothing else
/// (magic, version and ranges are the caller's, see validateDatagramHeader()). Cost: O(1).
std::optional<DatagramHeader> decodeDatagramHeader(QByteArrayView bytes);

/// Number of bands B = ceil(m / bandRows); 0 when bandRows is 0.
int bandCount(const DatagramHeader& header);

/// Number of interleaved (unprotected) rows in part j of a frame: #{k in [p, m) : (k − p) mod P == j}.
int interleavedRowCount(const DatagramHeader& header);

/// Exact datagram size implied by a header (header, exponents, rows, tag). Header must be range-valid.
int expectedDatagramSize(const DatagramHeader& header);

/// True when the range fields are consistent: 1 ≤ P ≤ kMaxParts, j < P, 1 ≤ m ≤ kMaxRows, p ≤ m, bandRows ≥ 1,
/// type is CoefficientFrame.
bool headerRangesValid(const DatagramHeader& header);

/// Big-endian helpers for the payload (int16 values), used by the codec. `at` must leave room: callers check.
void appendInt16(QByteArray& out, std::int16_t value);
std::int16_t readInt16(const char* at);

}  // namespace sc::session
