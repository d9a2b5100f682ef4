#include "session/password_auth.h"

#include <QtCore/QCryptographicHash>
#include <QtCore/QMessageAuthenticationCode>
#include <QtCore/QRandomGenerator>
#include <QtNetwork/QPasswordDigestor>

#include <vector>

namespace sc::session {

QByteArray secureRandomBytes(int count) {
  std::vector<quint32> words(static_cast<std::size_t>((count + 3) / 4));
  QRandomGenerator::system()->fillRange(words.data(), static_cast<qsizetype>(words.size()));
  return QByteArray(reinterpret_cast<const char*>(words.data()), count);
}

QByteArray derivePasswordKey(const QString& password, QByteArrayView salt, std::uint32_t iterations) {
  return QPasswordDigestor::deriveKeyPbkdf2(QCryptographicHash::Sha256, password.toUtf8(), salt.toByteArray(),
                                            static_cast<int>(iterations), kMacSize);
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
  unsigned char difference = 0;
  for (qsizetype i = 0; i < a.size(); ++i) {
    difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  }
  return difference == 0;
}

}  // namespace sc::session
