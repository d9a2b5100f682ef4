#pragma once
// The path-open datagram (client → host; byte layout in wire_format.h, "Path-open datagram"): it tells the host
// which UDP address to send a client's coefficient datagrams to, and keeps NAT bindings alive. Pure codec.

#include "session/lock_messages.h"
#include "session/wire_format.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <functional>
#include <optional>

namespace sc::session {

/// The exact kPathOpenSize bytes a client sends. `key`: its datagram key; `token`: kPathTokenSize bytes.
/// Cost: one HMAC over 22 bytes.
QByteArray encodePathOpen(std::uint16_t peerId, QByteArrayView token, const QByteArray& key);

/// Why the host dropped a path-open datagram. `None`: accepted.
enum class PathOpenError : std::uint8_t { None, Truncated, Stranger, BadTag, Malformed, Count };

const char* toString(PathOpenError error);

/// What the host knows of a joined client: its datagram key and path token.
struct PathCredentials {
  QByteArray key;
  QByteArray token;
};

/// Checks a datagram in the order of wire_format.h (length, known peer, tag, magic/version/type, token) and
/// returns the peer id it opens the path for. `lookup` maps a peer id to its credentials (nullopt: unknown peer).
/// Never reads outside `bytes`; the token comparison is constant-time. Cost: one HMAC over 22 bytes.
struct PathOpenResult {
  PathOpenError error = PathOpenError::Truncated;
  PeerId peer = kNoPeer;  ///< set when error == None
};
PathOpenResult decodePathOpen(QByteArrayView bytes,
                              const std::function<std::optional<PathCredentials>(PeerId)>& lookup);

}  // namespace sc::session
