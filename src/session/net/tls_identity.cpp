#include "session/net/tls_identity.h"

#include <QtCore/QCryptographicHash>
#include <QtCore/QDir>
#include <QtCore/QFile>
#include <QtCore/QSaveFile>
#include <QtCore/QStandardPaths>
#include <QtCore/QStringList>

#include <openssl/bio.h>
#include <openssl/bn.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <memory>

namespace sc::session {
namespace {

constexpr long kValidFromSeconds = -3600;                 ///< tolerate clocks an hour behind
constexpr long kValidForSeconds = 20L * 365 * 24 * 3600;  ///< the pin should outlive the installation
constexpr int kSerialBits = 128;
const QString kKeyFile = tlsIdentityFiles().key;
const QString kCertificateFile = tlsIdentityFiles().certificate;

template <typename T, void (*Free)(T*)>
struct OpenSslDeleter {
  void operator()(T* p) const { Free(p); }
};
using PKey = std::unique_ptr<EVP_PKEY, OpenSslDeleter<EVP_PKEY, EVP_PKEY_free>>;
using Certificate = std::unique_ptr<X509, OpenSslDeleter<X509, X509_free>>;
using Bio = std::unique_ptr<BIO, OpenSslDeleter<BIO, BIO_free_all>>;
using BigNum = std::unique_ptr<BIGNUM, OpenSslDeleter<BIGNUM, BN_free>>;

/// Sets `error` to `why` plus OpenSSL's first queued reason, clears OpenSSL's error queue; returns nullopt.
std::nullopt_t opensslFailure(QString* error, const QString& why) {
  if (error) {
    const unsigned long code = ERR_get_error();
    *error = code == 0 ? why : QStringLiteral("%1 (%2)").arg(why, QString::fromLatin1(ERR_reason_error_string(code)));
  }
  ERR_clear_error();
  return std::nullopt;
}

/// The PEM text a write function puts into a memory BIO; empty on failure.
template <typename Write>
QByteArray pem(Write write) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || write(bio.get()) != 1) return {};
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio.get(), &data);
  return size > 0 ? QByteArray(data, static_cast<qsizetype>(size)) : QByteArray();
}

/// Adds the v3 extension `nid` = `value` (OpenSSL's configuration syntax), issued by `issuer` (x509 itself when
/// self-signed).
bool addExtension(X509* x509, X509* issuer, int nid, const QString& value) {
  X509V3_CTX context;
  X509V3_set_ctx_nodb(&context);
  X509V3_set_ctx(&context, issuer, x509, nullptr, nullptr, 0);
  const QByteArray text = value.toUtf8();
  X509_EXTENSION* extension = X509V3_EXT_conf_nid(nullptr, &context, nid, text.constData());
  if (!extension) return false;
  const bool added = X509_add_ext(x509, extension, -1) == 1;
  X509_EXTENSION_free(extension);
  return added;
}

/// The profile's extensions: a CA's basic constraints and key usage, a server's subject alternative names.
bool addExtensions(X509* x509, X509* issuer, const CertificateProfile& profile) {
  if (profile.certificateAuthority) {
    return addExtension(x509, issuer, NID_basic_constraints, QStringLiteral("critical,CA:TRUE")) &&
           addExtension(x509, issuer, NID_key_usage, QStringLiteral("critical,keyCertSign,cRLSign")) &&
           addExtension(x509, issuer, NID_subject_key_identifier, QStringLiteral("hash"));
  }
  QStringList names;
  for (const QString& dns : profile.dnsNames) names << QStringLiteral("DNS:") + dns;
  for (const QString& ip : profile.ipAddresses) names << QStringLiteral("IP:") + ip;
  if (names.isEmpty()) return true;
  return addExtension(x509, issuer, NID_subject_alt_name, names.join(QLatin1Char(','))) &&
         addExtension(x509, issuer, NID_ext_key_usage, QStringLiteral("serverAuth"));
}

/// Fills and signs `x509` for `key`: self-signed when `issuer` is null, else issued by `issuer` (its certificate
/// and key).
bool fillCertificate(X509* x509, EVP_PKEY* key, const CertificateProfile& profile, X509* issuer = nullptr,
                     EVP_PKEY* issuerKey = nullptr) {
  BigNum serial(BN_new());
  if (!serial || BN_rand(serial.get(), kSerialBits, BN_RAND_TOP_ANY, BN_RAND_BOTTOM_ANY) != 1) return false;
  if (!BN_to_ASN1_INTEGER(serial.get(), X509_get_serialNumber(x509))) return false;
  if (X509_set_version(x509, 2) != 1) return false;  // X.509 v3
  if (!X509_gmtime_adj(X509_getm_notBefore(x509), kValidFromSeconds)) return false;
  if (!X509_gmtime_adj(X509_getm_notAfter(x509), kValidForSeconds)) return false;
  if (X509_set_pubkey(x509, key) != 1) return false;
  X509_NAME* name = X509_get_subject_name(x509);
  const QByteArray cn = profile.commonName.toUtf8().left(64);  // the X.520 upper bound of a common name
  if (X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_UTF8, reinterpret_cast<const unsigned char*>(cn.constData()),
                                 static_cast<int>(cn.size()), -1, 0) != 1) {
    return false;
  }
  if (X509_set_issuer_name(x509, issuer ? X509_get_subject_name(issuer) : name) != 1) return false;
  if (!addExtensions(x509, issuer ? issuer : x509, profile)) return false;
  return X509_sign(x509, issuerKey ? issuerKey : key, EVP_sha256()) > 0;
}

bool writePrivate(const QString& path, const QByteArray& bytes, QString* error) {
  QSaveFile file(path);
  if (!file.open(QIODevice::WriteOnly) || !file.setPermissions(QFile::ReadOwner | QFile::WriteOwner) ||
      file.write(bytes) != bytes.size() || !file.commit()) {
    if (error) *error = QStringLiteral("cannot write %1: %2").arg(path, file.errorString());
    return false;
  }
  return true;
}

/// True when the PEM private key belongs to the PEM certificate (X509_check_private_key).
bool keyMatches(const QByteArray& keyPem, const QByteArray& certificatePem) {
  Bio keyBio(BIO_new_mem_buf(keyPem.constData(), static_cast<int>(keyPem.size())));
  Bio certificateBio(BIO_new_mem_buf(certificatePem.constData(), static_cast<int>(certificatePem.size())));
  if (!keyBio || !certificateBio) return false;
  PKey key(PEM_read_bio_PrivateKey(keyBio.get(), nullptr, nullptr, nullptr));
  Certificate x509(PEM_read_bio_X509(certificateBio.get(), nullptr, nullptr, nullptr));
  const bool matches = key && x509 && X509_check_private_key(x509.get(), key.get()) == 1;
  ERR_clear_error();
  return matches;
}

bool isHexDigit(QChar c) {
  const char16_t u = c.unicode();
  return (u >= u'0' && u <= u'9') || (u >= u'a' && u <= u'f') || (u >= u'A' && u <= u'F');
}

}  // namespace

QByteArray TlsIdentity::fingerprint() const { return certificateFingerprint(certificate); }

QByteArray certificateFingerprint(const QSslCertificate& certificate) {
  return certificate.isNull() ? QByteArray() : certificate.digest(QCryptographicHash::Sha256);
}

std::optional<TlsIdentity> generateTlsIdentity(const QString& commonName, QString* error) {
  CertificateProfile profile;
  profile.commonName = commonName;
  return generateTlsIdentity(profile, nullptr, error);
}

std::optional<TlsIdentity> generateTlsIdentity(const CertificateProfile& profile, const TlsIdentity* issuer,
                                               QString* error) {
  PKey issuerKey;
  Certificate issuerCertificate;
  if (issuer) {
    const QByteArray keyPem = issuer->privateKey.toPem();
    const QByteArray certificatePem = issuer->certificate.toPem();
    Bio keyBio(BIO_new_mem_buf(keyPem.constData(), static_cast<int>(keyPem.size())));
    Bio certificateBio(BIO_new_mem_buf(certificatePem.constData(), static_cast<int>(certificatePem.size())));
    if (keyBio) issuerKey.reset(PEM_read_bio_PrivateKey(keyBio.get(), nullptr, nullptr, nullptr));
    if (certificateBio) issuerCertificate.reset(PEM_read_bio_X509(certificateBio.get(), nullptr, nullptr, nullptr));
    if (!issuerKey || !issuerCertificate) return opensslFailure(error, QStringLiteral("unreadable issuer"));
  }
  PKey key(EVP_EC_gen("P-256"));
  if (!key) return opensslFailure(error, QStringLiteral("key generation failed"));
  Certificate x509(X509_new());
  if (!x509 || !fillCertificate(x509.get(), key.get(), profile, issuerCertificate.get(), issuerKey.get())) {
    return opensslFailure(error, QStringLiteral("certificate creation failed"));
  }
  const QByteArray keyPem =
      pem([&](BIO* bio) { return PEM_write_bio_PrivateKey(bio, key.get(), nullptr, nullptr, 0, nullptr, nullptr); });
  const QByteArray certificatePem = pem([&](BIO* bio) { return PEM_write_bio_X509(bio, x509.get()); });
  TlsIdentity identity{QSslCertificate(certificatePem, QSsl::Pem), QSslKey(keyPem, QSsl::Ec, QSsl::Pem)};
  if (identity.certificate.isNull() || identity.privateKey.isNull()) {
    return opensslFailure(error, QStringLiteral("Qt could not read the generated key or certificate"));
  }
  return identity;
}

std::optional<TlsIdentity> loadOrCreateTlsIdentity(const QString& directory, QString* error) {
  const QDir dir(directory);
  const QString keyPath = dir.filePath(kKeyFile);
  const QString certificatePath = dir.filePath(kCertificateFile);
  QFile keyFile(keyPath);
  QFile certificateFile(certificatePath);
  if (keyFile.exists() != certificateFile.exists()) {
    // One half of a stored identity: never repaired by generating a new one (the fingerprint clients pinned would
    // change silently, and the remaining file would be overwritten).
    if (error) {
      *error = QStringLiteral(
                   "the host identity in %1 is incomplete: %2 is missing (restore it from a backup, or "
                   "remove %3 as well to create a new identity with a new fingerprint)")
                   .arg(directory, keyFile.exists() ? kCertificateFile : kKeyFile,
                        keyFile.exists() ? kKeyFile : kCertificateFile);
    }
    return std::nullopt;
  }
  if (keyFile.exists() && certificateFile.exists()) {
    if (!keyFile.open(QIODevice::ReadOnly) || !certificateFile.open(QIODevice::ReadOnly)) {
      if (error) {
        *error = QStringLiteral("cannot read the host identity in %1: %2")
                     .arg(directory, keyFile.isOpen() ? certificateFile.errorString() : keyFile.errorString());
      }
      return std::nullopt;
    }
    const QByteArray certificatePem = certificateFile.readAll();
    const QByteArray keyPem = keyFile.readAll();
    TlsIdentity identity{QSslCertificate(certificatePem, QSsl::Pem), QSslKey(keyPem, QSsl::Ec, QSsl::Pem)};
    if (identity.certificate.isNull() || identity.privateKey.isNull() || !keyMatches(keyPem, certificatePem)) {
      if (error) *error = QStringLiteral("%1 does not hold a matching host key and certificate").arg(directory);
      return std::nullopt;
    }
    return identity;
  }
  if (!QDir().mkpath(directory) ||
      !QFile::setPermissions(directory, QFile::ReadOwner | QFile::WriteOwner | QFile::ExeOwner)) {
    if (error) *error = QStringLiteral("cannot create %1").arg(directory);
    return std::nullopt;
  }
  std::optional<TlsIdentity> identity = generateTlsIdentity(QStringLiteral("ShapeCast host"), error);
  if (!identity) return std::nullopt;
  if (!writePrivate(keyPath, identity->privateKey.toPem(), error) ||
      !writePrivate(certificatePath, identity->certificate.toPem(), error)) {
    return std::nullopt;
  }
  return identity;
}

TlsIdentityFiles tlsIdentityFiles() { return {QStringLiteral("host-key.pem"), QStringLiteral("host-cert.pem")}; }

QString defaultTlsIdentityDirectory() {
  return QDir(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)).filePath(QStringLiteral("tls"));
}

QString formatFingerprint(const QByteArray& fingerprint) {
  return QString::fromLatin1(fingerprint.toHex(':').toUpper());
}

std::optional<QByteArray> parseFingerprint(const QString& text) {
  QByteArray hex;
  for (const QChar c : text) {
    if (c == QLatin1Char(':') || c == QLatin1Char(' ')) continue;
    if (!isHexDigit(c)) return std::nullopt;
    hex.append(c.toLatin1());
  }
  if (hex.size() != 2 * kFingerprintSize) return std::nullopt;
  return QByteArray::fromHex(hex);
}

}  // namespace sc::session
