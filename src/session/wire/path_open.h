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
enum class PathOpenError : std::uint8_t { None, Truncated, Stranger, BadTag, Malformed, Replayed, Count };

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

}  // namespace sc::session
