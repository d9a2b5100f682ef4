#include "session/wire/datagram_mac.h"

#include <openssl/core_names.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/params.h>

#include <cstdlib>
#include <utility>

namespace sc::session {
namespace {

struct MacDeleter {
  void operator()(EVP_MAC* mac) const { EVP_MAC_free(mac); }
};
struct MacContextDeleter {
  void operator()(EVP_MAC_CTX* context) const { EVP_MAC_CTX_free(context); }
};

/// An OpenSSL failure here means a broken installation (HMAC-SHA256 is always available): not recoverable.
void require(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

struct DatagramMac::Context {
  std::unique_ptr<EVP_MAC_CTX, MacContextDeleter> context;
};

DatagramMac::DatagramMac(QByteArrayView key) : m_context(std::make_unique<Context>()) {
  const std::unique_ptr<EVP_MAC, MacDeleter> mac(EVP_MAC_fetch(nullptr, "HMAC", nullptr));
  require(mac != nullptr);
  m_context->context.reset(EVP_MAC_CTX_new(mac.get()));
  require(m_context->context != nullptr);
  char digest[] = "SHA256";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string(OSSL_MAC_PARAM_DIGEST, digest, 0),
                               OSSL_PARAM_construct_end()};
  // An empty key is valid HMAC; OpenSSL wants a non-null pointer for it.
  static const unsigned char kEmpty = 0;
  const auto* keyBytes = key.isEmpty() ? &kEmpty : reinterpret_cast<const unsigned char*>(key.data());
  require(EVP_MAC_init(m_context->context.get(), keyBytes, static_cast<std::size_t>(key.size()), params) == 1);
}

DatagramMac::~DatagramMac() = default;
DatagramMac::DatagramMac(DatagramMac&&) noexcept = default;
DatagramMac& DatagramMac::operator=(DatagramMac&&) noexcept = default;

DatagramTag DatagramMac::tag(std::initializer_list<QByteArrayView> parts) const {
  EVP_MAC_CTX* context = m_context->context.get();
  // Re-initialising with no key keeps the key set at construction (OpenSSL 3 EVP_MAC_init): no allocation.
  require(EVP_MAC_init(context, nullptr, 0, nullptr) == 1);
  for (const QByteArrayView part : parts) {
    require(EVP_MAC_update(context, reinterpret_cast<const unsigned char*>(part.data()),
                           static_cast<std::size_t>(part.size())) == 1);
  }
  unsigned char full[EVP_MAX_MD_SIZE];
  std::size_t length = 0;
  require(EVP_MAC_final(context, full, &length, sizeof full) == 1 && length >= kTagSize);
  DatagramTag tag{};
  for (int i = 0; i < kTagSize; ++i) tag[static_cast<std::size_t>(i)] = static_cast<char>(full[i]);
  return tag;
}

bool DatagramMac::verify(std::initializer_list<QByteArrayView> parts, QByteArrayView tag) const {
  const DatagramTag expected = this->tag(parts);
  return constantTimeEqual(QByteArrayView(expected.data(), kTagSize), tag);
}

bool constantTimeEqual(QByteArrayView a, QByteArrayView b) {
  if (a.size() != b.size()) return false;
  return CRYPTO_memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size())) == 0;
}

}  // namespace sc::session
