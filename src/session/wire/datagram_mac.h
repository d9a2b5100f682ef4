#pragma once
// Per-peer datagram MAC: HMAC-SHA256 under one key, truncated to kTagSize bytes, on an OpenSSL EVP_MAC context that
// is keyed once (construction) and only re-initialised per datagram (Issue 14: a new Qt HMAC object per datagram
// cost 3.75 µs per 378-byte datagram, this 0.8 µs; bench/datagram_crypto_bench.cpp). Tags are compared with
// CRYPTO_memcmp (constant time).

#include "session/wire/wire_format.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <array>
#include <initializer_list>
#include <memory>

namespace sc::session {

/// A truncated HMAC-SHA256 tag.
using DatagramTag = std::array<char, kTagSize>;

class DatagramMac {
 public:
  /// @param[in] key  the HMAC key (any length; the datagram key from the Welcome is 32 bytes).
  explicit DatagramMac(QByteArrayView key);
  ~DatagramMac();
  DatagramMac(DatagramMac&&) noexcept;
  DatagramMac& operator=(DatagramMac&&) noexcept;
  DatagramMac(const DatagramMac&) = delete;
  DatagramMac& operator=(const DatagramMac&) = delete;

  /// HMAC-SHA256(key, parts[0] ‖ parts[1] ‖ …) truncated to kTagSize. Cost: one HMAC over the bytes, no allocation.
  DatagramTag tag(std::initializer_list<QByteArrayView> parts) const;
  /// True when `tag` (kTagSize bytes) is the tag of the parts; compared in constant time. A wrong size is false.
  bool verify(std::initializer_list<QByteArrayView> parts, QByteArrayView tag) const;

 private:
  struct Context;
  std::unique_ptr<Context> m_context;  ///< never null except after a move
};

/// Constant-time equality of two byte strings (CRYPTO_memcmp); false when the sizes differ.
bool constantTimeEqual(QByteArrayView a, QByteArrayView b);

}  // namespace sc::session
