#include "session/wire/password_auth.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <QtCore/QCryptographicHash>
#include <QtCore/QMessageAuthenticationCode>
#include <QtCore/QRandomGenerator>

#include <vector>

namespace sc::session {

QByteArray secureRandomBytes(int count) {
  std::vector<quint32> words(static_cast<std::size_t>((count + 3) / 4));
  QRandomGenerator::system()->fillRange(words.data(), static_cast<qsizetype>(words.size()));
  return QByteArray(reinterpret_cast<const char*>(words.data()), count);
}

QByteArray derivePasswordKey(const QString& password, QByteArrayView salt, std::uint32_t iterations) {
  // OpenSSL's PBKDF2-HMAC-SHA256 (the same derivation Qt's QPasswordDigestor made; the wire format is unchanged), so
  // that the wire and engine layers need no Qt Network. Returns empty only if OpenSSL fails (out of memory).
  QByteArray utf8 = password.toUtf8();
  QByteArray key(kMacSize, Qt::Uninitialized);
  const int ok = PKCS5_PBKDF2_HMAC(utf8.constData(), static_cast<int>(utf8.size()),
                                   reinterpret_cast<const unsigned char*>(salt.data()), static_cast<int>(salt.size()),
                                   static_cast<int>(iterations), EVP_sha256(), static_cast<int>(key.size()),
                                   reinterpret_cast<unsigned char*>(key.data()));
  utf8.fill('\0');  // its own buffer: the password's bytes do not outlive the derivation
  return ok == 1 ? key : QByteArray();
}

Challenge makeChallenge(QByteArrayView salt, std::uint32_t iterations) {
  return Challenge{secureRandomBytes(kNonceSize), salt.toByteArray(), iterations};
}

ChallengeResponse answerChallenge(QByteArrayView key, const Challenge& challenge, QByteArrayView channelBinding) {
  QMessageAuthenticationCode mac(QCryptographicHash::Sha256, key.toByteArray());
  mac.addData(QByteArray("SC-auth2"));
  mac.addData(challenge.nonce);
  mac.addData(channelBinding.data(), channelBinding.size());
  return ChallengeResponse{mac.result()};
}

bool verifyChallengeResponse(QByteArrayView key, const Challenge& challenge, QByteArrayView channelBinding,
                             const ChallengeResponse& response) {
  return constantTimeEquals(answerChallenge(key, challenge, channelBinding).mac, response.mac);
}

bool constantTimeEquals(QByteArrayView a, QByteArrayView b) {
  if (a.size() != b.size()) return false;
  return CRYPTO_memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size())) == 0;
}

}  // namespace sc::session
