#include "session/wire/datagram_cipher.h"

#include <QtCore/QtEndian>

#include <openssl/core_names.h>
#include <openssl/evp.h>
#include <openssl/kdf.h>
#include <openssl/params.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <string_view>

namespace sc::session {
namespace {

constexpr int kKeySize = 16;    ///< AES-128
constexpr int kNonceSize = 12;  ///< GCM's 96-bit IV

struct CipherContextDeleter {
  void operator()(EVP_CIPHER_CTX* context) const { EVP_CIPHER_CTX_free(context); }
};
struct KdfDeleter {
  void operator()(EVP_KDF* kdf) const { EVP_KDF_free(kdf); }
};
struct KdfContextDeleter {
  void operator()(EVP_KDF_CTX* context) const { EVP_KDF_CTX_free(context); }
};

/// An OpenSSL failure on a valid call means a broken installation (AES-GCM and HKDF are always there).
void require(bool ok) {
  if (!ok) std::abort();
}

const unsigned char* bytes(QByteArrayView view) { return reinterpret_cast<const unsigned char*>(view.data()); }

std::array<unsigned char, kKeySize> deriveKey(QByteArrayView datagramKey, DatagramDirection direction) {
  const std::unique_ptr<EVP_KDF, KdfDeleter> kdf(EVP_KDF_fetch(nullptr, "HKDF", nullptr));
  require(kdf != nullptr);
  const std::unique_ptr<EVP_KDF_CTX, KdfContextDeleter> context(EVP_KDF_CTX_new(kdf.get()));
  require(context != nullptr);
  std::string_view info = direction == DatagramDirection::HostToClient ? "ShapeCast v3 datagram host->client"
                                                                       : "ShapeCast v3 datagram client->host";
  char digest[] = "SHA256";
  static const unsigned char kEmpty = 0;
  const OSSL_PARAM params[] = {
      OSSL_PARAM_construct_utf8_string(OSSL_KDF_PARAM_DIGEST, digest, 0),
      OSSL_PARAM_construct_octet_string(
          OSSL_KDF_PARAM_KEY, const_cast<unsigned char*>(datagramKey.isEmpty() ? &kEmpty : bytes(datagramKey)),
          static_cast<std::size_t>(datagramKey.size())),
      OSSL_PARAM_construct_octet_string(OSSL_KDF_PARAM_INFO, const_cast<char*>(info.data()), info.size()),
      OSSL_PARAM_construct_end()};
  std::array<unsigned char, kKeySize> key{};
  require(EVP_KDF_derive(context.get(), key.data(), key.size(), params) == 1);
  return key;
}

}  // namespace

struct DatagramCipher::Context {
  std::unique_ptr<EVP_CIPHER_CTX, CipherContextDeleter> seal{EVP_CIPHER_CTX_new()};
  std::unique_ptr<EVP_CIPHER_CTX, CipherContextDeleter> open{EVP_CIPHER_CTX_new()};
};

DatagramCipher::DatagramCipher(QByteArrayView datagramKey, DatagramDirection direction)
    : m_context(std::make_unique<Context>()), m_direction(direction) {
  require(m_context->seal != nullptr && m_context->open != nullptr);
  const std::array<unsigned char, kKeySize> key = deriveKey(datagramKey, direction);
  // Keyed once; the default GCM IV length is 12 bytes, so per datagram only the IV is set.
  require(EVP_EncryptInit_ex(m_context->seal.get(), EVP_aes_128_gcm(), nullptr, key.data(), nullptr) == 1);
  require(EVP_DecryptInit_ex(m_context->open.get(), EVP_aes_128_gcm(), nullptr, key.data(), nullptr) == 1);
}

DatagramCipher::~DatagramCipher() = default;
DatagramCipher::DatagramCipher(DatagramCipher&&) noexcept = default;
DatagramCipher& DatagramCipher::operator=(DatagramCipher&&) noexcept = default;

namespace {

std::array<unsigned char, kNonceSize> nonce(DatagramDirection direction, std::uint64_t sequence) {
  std::array<unsigned char, kNonceSize> iv{};
  qToBigEndian(static_cast<std::uint32_t>(direction), iv.data());
  qToBigEndian(sequence, iv.data() + 4);
  return iv;
}

}  // namespace

void DatagramCipher::seal(std::uint64_t sequence, QByteArrayView aad, QByteArrayView plaintext, QByteArray& out) const {
  EVP_CIPHER_CTX* context = m_context->seal.get();
  const auto iv = nonce(m_direction, sequence);
  require(EVP_EncryptInit_ex(context, nullptr, nullptr, nullptr, iv.data()) == 1);
  int length = 0;
  require(EVP_EncryptUpdate(context, nullptr, &length, bytes(aad), static_cast<int>(aad.size())) == 1);
  const qsizetype start = out.size();
  out.resize(start + plaintext.size() + kTagSize);
  auto* cipher = reinterpret_cast<unsigned char*>(out.data() + start);
  require(EVP_EncryptUpdate(context, cipher, &length, bytes(plaintext), static_cast<int>(plaintext.size())) == 1);
  int tail = 0;
  require(EVP_EncryptFinal_ex(context, cipher + length, &tail) == 1 && length + tail == plaintext.size());
  require(EVP_CIPHER_CTX_ctrl(context, EVP_CTRL_GCM_GET_TAG, kTagSize, cipher + plaintext.size()) == 1);
}

bool DatagramCipher::open(std::uint64_t sequence, QByteArrayView aad, QByteArrayView sealed,
                          QByteArray& plaintext) const {
  if (sealed.size() < kTagSize) return false;
  EVP_CIPHER_CTX* context = m_context->open.get();
  const auto iv = nonce(m_direction, sequence);
  const QByteArrayView ciphertext = sealed.first(sealed.size() - kTagSize);
  std::array<unsigned char, kTagSize> tag{};
  std::copy_n(bytes(sealed.last(kTagSize)), kTagSize, tag.begin());
  plaintext.resize(ciphertext.size());
  int length = 0;
  if (EVP_DecryptInit_ex(context, nullptr, nullptr, nullptr, iv.data()) != 1) return false;
  if (EVP_DecryptUpdate(context, nullptr, &length, bytes(aad), static_cast<int>(aad.size())) != 1) return false;
  auto* out = reinterpret_cast<unsigned char*>(plaintext.data());
  if (EVP_DecryptUpdate(context, out, &length, bytes(ciphertext), static_cast<int>(ciphertext.size())) != 1) {
    return false;
  }
  if (EVP_CIPHER_CTX_ctrl(context, EVP_CTRL_GCM_SET_TAG, kTagSize, tag.data()) != 1) return false;
  int tail = 0;
  return EVP_DecryptFinal_ex(context, out + length, &tail) == 1;  // checks the tag (constant time)
}

}  // namespace sc::session
