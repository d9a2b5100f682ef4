#pragma once
// Password check by challenge-response (docs/protocol.md, "Authentication"). The password never crosses the wire:
//   key = PBKDF2-HMAC-SHA256(password UTF-8, salt, iterations, 32 bytes)   (salt, iterations: from the Challenge)
//   mac = HMAC-SHA256(key, "SC-auth1" ‖ nonce)                            (nonce: fresh per connection)
// The host keeps only (salt, iterations, key), never the password. A session without a password sends no
// Challenge. Note: an eavesdropper who records (nonce, mac) can still try passwords offline; PBKDF2 slows that
// down, and a strong password or an encrypted transport (TLS) is the real defence.

#include "session/control_messages.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <cstdint>

namespace sc::session {

inline constexpr std::uint32_t kDefaultPbkdf2Iterations = 100000;  ///< host default (client max: kMaxPbkdf2Iterations)

/// `count` bytes from the system's cryptographically secure generator (QRandomGenerator::system()).
QByteArray secureRandomBytes(int count);

/// PBKDF2-HMAC-SHA256(password, salt, iterations) → kMacSize bytes. iterations ≥ 1. Cost: O(iterations).
QByteArray derivePasswordKey(const QString& password, QByteArrayView salt, std::uint32_t iterations);

/// A fresh Challenge for one connection: random nonce, the session's salt and iteration count.
Challenge makeChallenge(QByteArrayView salt, std::uint32_t iterations);

/// The client's answer: HMAC-SHA256(key, "SC-auth1" ‖ nonce).
ChallengeResponse answerChallenge(QByteArrayView key, const Challenge& challenge);

/// Host side: true when `response` proves knowledge of the password behind `key`. Constant time in the MAC.
bool verifyChallengeResponse(QByteArrayView key, const Challenge& challenge, const ChallengeResponse& response);

/// Equality of two byte strings in time that depends only on their lengths (not on where they differ).
bool constantTimeEquals(QByteArrayView a, QByteArrayView b);

}  // namespace sc::session
