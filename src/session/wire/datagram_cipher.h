#pragma once
// AEAD for coefficient datagrams (protocol version 3): AES-128-GCM on an OpenSSL EVP_CIPHER_CTX keyed once per
// peer and direction; per datagram only the 96-bit nonce is set (Issue 14: 0.32 µs per 378-byte datagram measured,
// bench/datagram_crypto_bench.cpp).
//
// Keys: HKDF-SHA256 (RFC 5869) of the 32-byte datagram key from the Welcome, empty salt, info "ShapeCast v3
// datagram host->client" or "... client->host", 16 bytes each: the two directions never share a key, so they can
// never reuse a (key, nonce) pair. Nonce: u32 BE direction id (1 host → client, 2 client → host) ‖ u64 BE extended
// sequence S (never wraps, one per datagram, so one nonce per key and datagram). The header is additional
// authenticated data (readable, not secret); the payload is ciphertext; the 16-byte GCM tag ends the datagram.
// Not thread-safe: one object per peer and direction, on one thread.

#include "session/wire/wire_format.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <memory>

namespace sc::session {

enum class DatagramDirection : std::uint32_t { HostToClient = 1, ClientToHost = 2 };

class DatagramCipher {
 public:
  /// @param[in] datagramKey  the per-client key of the Welcome (any length; 32 bytes on the wire); the cipher key
  ///            for `direction` is derived from it (HKDF, above). Cost: one HKDF and one key schedule.
  DatagramCipher(QByteArrayView datagramKey, DatagramDirection direction);
  ~DatagramCipher();
  DatagramCipher(DatagramCipher&&) noexcept;
  DatagramCipher& operator=(DatagramCipher&&) noexcept;
  DatagramCipher(const DatagramCipher&) = delete;
  DatagramCipher& operator=(const DatagramCipher&) = delete;

  /// Appends Enc(plaintext) ‖ tag (kTagSize bytes) to `out`, with `aad` authenticated (`aad` may view bytes of
  /// `out`: it is consumed before `out` grows; `plaintext` must not). `sequence` must never repeat under one key (the
  /// caller's extended sequence). Cost: O(bytes).
  void seal(std::uint64_t sequence, QByteArrayView aad, QByteArrayView plaintext, QByteArray& out) const;
  /// Decrypts `sealed` (ciphertext ‖ tag) into `plaintext` (resized to sealed.size() − kTagSize) and checks the tag
  /// over `aad` and the ciphertext. False (plaintext unspecified) when shorter than a tag or not authentic.
  bool open(std::uint64_t sequence, QByteArrayView aad, QByteArrayView sealed, QByteArray& plaintext) const;

 private:
  struct Context;
  std::unique_ptr<Context> m_context;  ///< never null except after a move
  DatagramDirection m_direction;
};

}  // namespace sc::session
