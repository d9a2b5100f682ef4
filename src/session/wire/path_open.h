#pragma once
// The path-open datagram (client → host; byte layout in wire_format.h, "Path-open datagram"): it tells the host
// which UDP address to send a client's coefficient datagrams to, and keeps NAT bindings alive. Pure codec.

#include "session/wire/datagram_mac.h"
#include "session/wire/lock_messages.h"
#include "session/wire/wire_format.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <functional>
#include <optional>

namespace sc::session {

/// The exact kPathOpenSize bytes a client sends. `key`: its datagram key; `token`: kPathTokenSize bytes;
/// `sequence`: 1 for the first PathOpen after a Welcome, +1 for every later one (the host drops any sequence not
/// above the highest it accepted from that peer). Deterministic: the same arguments give the same bytes.
/// Cost: one HMAC over 26 bytes.
QByteArray encodePathOpen(std::uint16_t peerId, QByteArrayView token, std::uint32_t sequence, const QByteArray& key);

/// Why the host dropped a path-open datagram. `None`: accepted. `Replayed`: authentic, but its sequence is not
/// above the highest accepted for that peer (a recorded PathOpen resent, or an old one delivered late).
/// `WrongChallenge`: an authentic PathResponse that does not answer the peer's current challenge from the candidate
/// address and port (late, repeated, or from elsewhere).
enum class PathOpenError : std::uint8_t {
  None,
  Truncated,
  Stranger,
  BadTag,
  Malformed,
  Replayed,
  WrongChallenge,
  Count
};

const char* toString(PathOpenError error);

/// What the host knows of a joined client: the MAC keyed with its datagram key (kept per peer, not null), its path
/// token and the highest PathOpen sequence it accepted from it (0: none yet, so every sequence ≥ 1 is fresh).
struct PathCredentials {
  const DatagramMac* mac = nullptr;
  QByteArray token;
  std::uint32_t highestSequence = 0;
};

/// Checks a datagram in the order of wire_format.h (length, known peer, tag, magic/version/type, token, sequence)
/// and returns the peer id it opens the path for and its sequence. `lookup` maps a peer id to its credentials
/// (nullopt: unknown peer). Pure: the caller records `sequence` as the peer's new highest when error == None.
/// Never reads outside `bytes`; the tag and token comparisons are constant-time. Cost: one HMAC over 26 bytes.
struct PathOpenResult {
  PathOpenError error = PathOpenError::Truncated;
  PeerId peer = kNoPeer;       ///< set when error == None
  std::uint32_t sequence = 0;  ///< set when error == None
};
PathOpenResult decodePathOpen(QByteArrayView bytes,
                              const std::function<std::optional<PathCredentials>(PeerId)>& lookup);

/// A PathChallenge (host → client) or PathResponse (client → host), kPathProbeSize bytes (wire_format.h, "Path
/// challenge and response"): `type` is one of the two, `mac` the peer's (keyed with its datagram key).
/// Deterministic. Cost: one HMAC over 14 bytes.
QByteArray encodePathProbe(MessageType type, std::uint16_t peerId, std::uint64_t challenge, const DatagramMac& mac);

/// True when `bytes` has a probe's length and `type` in its type byte: cheap dispatch before authentication.
bool looksLikePathProbe(QByteArrayView bytes, MessageType type);

/// The peer id field of a datagram that looksLikePathProbe() (selects the MAC); kNoPeer when too short.
PeerId pathProbePeer(QByteArrayView bytes);

/// Checks a probe of `type` for a peer whose MAC is `mac` (order in wire_format.h: length and type, tag,
/// magic/version) and returns its challenge value; error != None when dropped. Never reads outside `bytes`.
struct PathProbeResult {
  PathOpenError error = PathOpenError::Truncated;
  std::uint64_t challenge = 0;  ///< set when error == None
};
PathProbeResult decodePathProbe(QByteArrayView bytes, MessageType type, const DatagramMac& mac);

}  // namespace sc::session
