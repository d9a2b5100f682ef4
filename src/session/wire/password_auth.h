#pragma once
// Password check by challenge-response (docs/protocol.md, "Authentication"). The password never crosses the wire:
//   key = PBKDF2-HMAC-SHA256(password UTF-8, salt, iterations, 32 bytes)   (salt, iterations: from the Challenge)
//   mac = HMAC-SHA256(key, "SC-auth2" ‖ nonce ‖ binding)                  (nonce: fresh per connection)
// binding is the channel binding: the SHA-256 of the host's TLS certificate as the client saw it in its own TLS
// handshake ("tls-server-end-point", RFC 5929); the host uses its own certificate's. A man in the middle who
// terminates the client's TLS with another certificate cannot relay the proof to the host: it is bound to the
// wrong certificate (docs/security.md). The host keeps only (salt, iterations, key), never the password. A session
// without a password sends no Challenge. The whole exchange runs inside TLS, so an eavesdropper sees no (nonce,
// mac); whoever the client really talks to (an unpinned impostor) can still try passwords offline against it,
// slowed by PBKDF2.

#include "session/wire/control_messages.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <cstdint>

namespace sc::session {

/// The host's default PBKDF2 count: 600,000 (OWASP's current guidance for PBKDF2-HMAC-SHA256). About 0.35 s to
/// derive (shared 2-core machine) once per session on the host and once per join on the client (docs/security.md,
/// "Hostile host").
inline constexpr std::uint32_t kDefaultPbkdf2Iterations = 600000;
/// The fewest PBKDF2 iterations a client accepts in a Challenge (ClientHandshakeConfig::minIterations): below it an
/// impostor host would get a proof it can attack at nearly HMAC speed (1 iteration: ~257,000 guesses per second).
/// Tests whose hosts use fewer lower it explicitly. The most: kMaxPbkdf2Iterations (wire_format.h).
inline constexpr std::uint32_t kMinPbkdf2Iterations = 100000;

/// `count` bytes from the system's cryptographically secure generator (QRandomGenerator::system()).
QByteArray secureRandomBytes(int count);

/// PBKDF2-HMAC-SHA256(password, salt, iterations) → kMacSize bytes. iterations ≥ 1. Cost: O(iterations).
QByteArray derivePasswordKey(const QString& password, QByteArrayView salt, std::uint32_t iterations);

/// A fresh Challenge for one connection: random nonce, the session's salt and iteration count.
Challenge makeChallenge(QByteArrayView salt, std::uint32_t iterations);

/// The client's answer: HMAC-SHA256(key, "SC-auth2" ‖ nonce ‖ channelBinding). channelBinding: the host
/// certificate's SHA-256 (kFingerprintSize bytes; empty only in tests of the state machines without TLS).
ChallengeResponse answerChallenge(QByteArrayView key, const Challenge& challenge, QByteArrayView channelBinding);

/// Host side: true when `response` proves knowledge of the password behind `key`, over the TLS channel whose
/// certificate hash is `channelBinding`. Constant time in the MAC.
bool verifyChallengeResponse(QByteArrayView key, const Challenge& challenge, QByteArrayView channelBinding,
                             const ChallengeResponse& response);

/// Equality of two byte strings in time that depends only on their lengths (not on where they differ):
/// OpenSSL's CRYPTO_memcmp.
bool constantTimeEquals(QByteArrayView a, QByteArrayView b);

}  // namespace sc::session
