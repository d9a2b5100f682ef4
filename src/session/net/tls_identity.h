#pragma once
// The host's TLS identity (docs/security.md): a self-signed X.509 certificate and its private key (ECDSA P-256),
// generated with OpenSSL on first use, stored in the application's data folder and reused, so that its SHA-256
// fingerprint stays the same across runs and clients can pin it (check it once, by voice or chat, with the host).
// Qt cannot create certificates, hence the small OpenSSL (libcrypto) part in tls_identity.cpp.

#include <QtCore/QByteArray>
#include <QtCore/QString>
#include <QtCore/QStringList>
#include <QtNetwork/QSslCertificate>
#include <QtNetwork/QSslKey>

#include <optional>

namespace sc::session {

inline constexpr int kFingerprintSize = 32;  ///< SHA-256 of the certificate's DER encoding

/// A certificate with its private key; both null in a default-constructed value.
struct TlsIdentity {
  QSslCertificate certificate;
  QSslKey privateKey;

  /// SHA-256 of the certificate's DER bytes (kFingerprintSize bytes): what clients pin, and the channel binding
  /// ("tls-server-end-point", RFC 5929) mixed into the password proof. Cost: one hash of ≈ 400 bytes.
  [[nodiscard]] QByteArray fingerprint() const;
};

/// Generates a fresh ECDSA P-256 key and a self-signed certificate (subject and issuer CN = `commonName`, random
/// 128-bit serial, valid from one hour ago for 20 years, SHA-256 signature). Returns nullopt with `error` set when
/// OpenSSL fails. Cost: one P-256 key generation and one signature.
std::optional<TlsIdentity> generateTlsIdentity(const QString& commonName, QString* error = nullptr);

/// What a generated certificate says besides its key (the broker's TLS in tests and scripts, local_nats_server.h).
struct CertificateProfile {
  QString commonName;
  bool certificateAuthority = false;  ///< basicConstraints CA:TRUE (critical), keyUsage keyCertSign, cRLSign
  QStringList dnsNames;     ///< subjectAltName DNS entries (a server certificate; with extKeyUsage serverAuth)
  QStringList ipAddresses;  ///< subjectAltName IP entries
};

/// As above, with `profile`'s extensions, issued and signed by `issuer` (its certificate's subject, its key), or
/// self-signed when `issuer` is null. Cost: one P-256 key generation and one signature.
std::optional<TlsIdentity> generateTlsIdentity(const CertificateProfile& profile, const TlsIdentity* issuer,
                                               QString* error = nullptr);

/// Loads `directory`/host-key.pem and host-cert.pem; only when both are absent (first use) generates an identity
/// and stores both (the folder is created with 0700, the files are written atomically with 0600 permissions).
/// Returns nullopt with `error` set (a readable sentence naming the file) when one of the two files is missing,
/// when they cannot be read or do not hold a matching key and certificate, or the folder cannot be written: an
/// existing identity is never replaced. Cost: two small file reads, or one generation and two writes.
std::optional<TlsIdentity> loadOrCreateTlsIdentity(const QString& directory, QString* error = nullptr);

/// The files of an identity in its folder: the key ("host-key.pem"), then the certificate ("host-cert.pem").
struct TlsIdentityFiles {
  QString key;
  QString certificate;
};
TlsIdentityFiles tlsIdentityFiles();

/// Where the host keeps its identity: QStandardPaths::AppDataLocation + "/tls" (needs the application name set).
QString defaultTlsIdentityDirectory();

/// SHA-256 of `certificate` (kFingerprintSize bytes; empty for a null certificate).
QByteArray certificateFingerprint(const QSslCertificate& certificate);

/// "AB:CD:…" (upper-case hex pairs joined by colons), as users compare them.
QString formatFingerprint(const QByteArray& fingerprint);

/// Parses 64 hex digits, with or without ':' / ' ' separators, in either case. nullopt for anything else.
std::optional<QByteArray> parseFingerprint(const QString& text);

}  // namespace sc::session
