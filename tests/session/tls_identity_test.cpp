// The host's TLS identity and the client's trust decisions (docs/security.md; src/session/net/tls_identity.cpp,
// tls_known_hosts.cpp): a generated certificate and its SHA-256 fingerprint, the identity stored on first use with
// owner-only permissions, fingerprint formatting and parsing, pinned / known / first-use verdicts, and the known-hosts
// store per host and port. No sockets.
#include "session/net/tls_identity.h"
#include "session/net/tls_known_hosts.h"

#include <gtest/gtest.h>

#include <QtCore/QCryptographicHash>
#include <QtCore/QFile>
#include <QtCore/QTemporaryDir>
#include <QtNetwork/QSslCertificate>
#include <QtNetwork/QSslCertificateExtension>

#include <optional>

namespace sc::session {
namespace {

TEST(TlsIdentity, GeneratedCertificateHasAStableSha256Fingerprint) {
  QString error;
  const std::optional<TlsIdentity> a = generateTlsIdentity(QStringLiteral("test"), &error);
  ASSERT_TRUE(a) << error.toStdString();
  EXPECT_FALSE(a->certificate.isNull());
  EXPECT_FALSE(a->privateKey.isNull());
  EXPECT_EQ(a->fingerprint().size(), kFingerprintSize);
  EXPECT_EQ(a->fingerprint(), a->certificate.digest(QCryptographicHash::Sha256));
  EXPECT_TRUE(a->certificate.isSelfSigned());
  const std::optional<TlsIdentity> b = generateTlsIdentity(QStringLiteral("test"));
  ASSERT_TRUE(b);
  EXPECT_NE(a->fingerprint(), b->fingerprint());  // fresh key each time
}

TEST(TlsIdentity, StoredOnFirstUseWithOwnerOnlyPermissionsAndReused) {
  QTemporaryDir temp;
  ASSERT_TRUE(temp.isValid());
  const QString dir = temp.filePath(QStringLiteral("tls"));
  QString error;
  const std::optional<TlsIdentity> first = loadOrCreateTlsIdentity(dir, &error);
  ASSERT_TRUE(first) << error.toStdString();
  const QString keyPath = dir + QStringLiteral("/host-key.pem");
  ASSERT_TRUE(QFile::exists(keyPath));
  const QFile::Permissions groupOrOther =
      QFile::ReadGroup | QFile::WriteGroup | QFile::ExeGroup | QFile::ReadOther | QFile::WriteOther | QFile::ExeOther;
  EXPECT_EQ(QFile::permissions(keyPath) & groupOrOther, QFile::Permissions());  // 0600: the owner only
  EXPECT_TRUE(QFile::permissions(keyPath) & QFile::ReadOwner);
  const std::optional<TlsIdentity> second = loadOrCreateTlsIdentity(dir, &error);
  ASSERT_TRUE(second) << error.toStdString();
  EXPECT_EQ(second->fingerprint(), first->fingerprint());
  // A key that does not belong to the certificate is refused, not silently replaced.
  const std::optional<TlsIdentity> other = generateTlsIdentity(QStringLiteral("other"));
  ASSERT_TRUE(other);
  QFile key(keyPath);
  ASSERT_TRUE(key.open(QIODevice::WriteOnly | QIODevice::Truncate));
  key.write(other->privateKey.toPem());
  key.close();
  EXPECT_FALSE(loadOrCreateTlsIdentity(dir, &error));
  EXPECT_FALSE(error.isEmpty());
}

// Issue 14, item 11: one file of a stored identity missing is reported, never repaired by generating a new identity
// (that would silently change the fingerprint every client pinned, and overwrite the remaining file).
TEST(TlsIdentity, AMissingCertificateOrKeyFileIsReportedNotRegenerated) {
  for (const QString& missing : {QStringLiteral("host-cert.pem"), QStringLiteral("host-key.pem")}) {
    QTemporaryDir temp;
    ASSERT_TRUE(temp.isValid());
    const QString dir = temp.filePath(QStringLiteral("tls"));
    QString error;
    ASSERT_TRUE(loadOrCreateTlsIdentity(dir, &error)) << error.toStdString();
    const QString kept = dir + (missing == QStringLiteral("host-key.pem") ? QStringLiteral("/host-cert.pem")
                                                                          : QStringLiteral("/host-key.pem"));
    QFile keptFile(kept);
    ASSERT_TRUE(keptFile.open(QIODevice::ReadOnly));
    const QByteArray keptBytes = keptFile.readAll();
    keptFile.close();
    ASSERT_TRUE(QFile::remove(dir + QLatin1Char('/') + missing));

    error.clear();
    EXPECT_FALSE(loadOrCreateTlsIdentity(dir, &error)) << missing.toStdString();
    EXPECT_TRUE(error.contains(missing)) << error.toStdString();
    EXPECT_TRUE(error.contains(QStringLiteral("missing"))) << error.toStdString();
    EXPECT_FALSE(QFile::exists(dir + QLatin1Char('/') + missing)) << "regenerated " << missing.toStdString();
    ASSERT_TRUE(keptFile.open(QIODevice::ReadOnly));
    EXPECT_EQ(keptFile.readAll(), keptBytes) << kept.toStdString() << " was overwritten";
  }
}

TEST(TlsIdentity, ACaSignsAServerCertificateThatNamesItsHosts) {
  // The broker's TLS in tests (local_nats_server.h): a CA, and a server certificate it issues.
  CertificateProfile authority;
  authority.commonName = QStringLiteral("test CA");
  authority.certificateAuthority = true;
  const std::optional<TlsIdentity> ca = generateTlsIdentity(authority, nullptr);
  ASSERT_TRUE(ca);
  EXPECT_TRUE(ca->certificate.isSelfSigned());
  CertificateProfile server;
  server.commonName = QStringLiteral("localhost");
  server.dnsNames = {QStringLiteral("localhost")};
  server.ipAddresses = {QStringLiteral("127.0.0.1")};
  QString error;
  const std::optional<TlsIdentity> issued = generateTlsIdentity(server, &*ca, &error);
  ASSERT_TRUE(issued) << error.toStdString();
  EXPECT_FALSE(issued->certificate.isSelfSigned());
  EXPECT_EQ(issued->certificate.issuerInfo(QSslCertificate::CommonName), QStringList{QStringLiteral("test CA")});
  const auto names = issued->certificate.subjectAlternativeNames();
  EXPECT_TRUE(names.values(QSsl::DnsEntry).contains(QStringLiteral("localhost")));
  EXPECT_TRUE(names.values(QSsl::IpAddressEntry).contains(QStringLiteral("127.0.0.1")));
  // Without a profile's extensions: the host identity as before (no CA flag, no names).
  const std::optional<TlsIdentity> plain = generateTlsIdentity(QStringLiteral("host"));
  ASSERT_TRUE(plain);
  EXPECT_TRUE(plain->certificate.extensions().isEmpty());
  EXPECT_FALSE(ca->certificate.extensions().isEmpty());
}

TEST(TlsIdentity, FingerprintsFormatAndParse) {
  const QByteArray fingerprint =
      QByteArray::fromHex("00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff");
  const QString text = formatFingerprint(fingerprint);
  EXPECT_EQ(text.left(9), QStringLiteral("00:11:22:"));
  EXPECT_EQ(parseFingerprint(text), fingerprint);
  EXPECT_EQ(parseFingerprint(text.toLower().remove(QLatin1Char(':'))), fingerprint);
  EXPECT_FALSE(parseFingerprint(text.left(text.size() - 1)));
  EXPECT_FALSE(parseFingerprint(QStringLiteral("zz") + text.mid(2)));
  EXPECT_FALSE(parseFingerprint(QString()));
}

TEST(TrustDecision, PinnedThenKnownThenFirstUse) {
  using V = FingerprintCheck::Verdict;
  const QByteArray a(32, '\x0a');
  const QByteArray b(32, '\x0b');
  EXPECT_EQ(checkFingerprint(a, a, std::nullopt, true).verdict, V::Pinned);
  const FingerprintCheck mismatch = checkFingerprint(a, b, a, true);  // a pin wins over the remembered entry
  EXPECT_EQ(mismatch.verdict, V::Mismatch);
  EXPECT_FALSE(mismatch.accepted());
  EXPECT_TRUE(mismatch.reason.contains(formatFingerprint(a)) && mismatch.reason.contains(formatFingerprint(b)));
  EXPECT_EQ(checkFingerprint(a, {}, a, true).verdict, V::Known);
  const FingerprintCheck changed = checkFingerprint(a, {}, b, true);
  EXPECT_EQ(changed.verdict, V::Changed);
  EXPECT_FALSE(changed.accepted());
  EXPECT_TRUE(changed.reason.contains(QStringLiteral("changed")));
  EXPECT_EQ(checkFingerprint(a, {}, std::nullopt, true).verdict, V::FirstUse);
  EXPECT_EQ(checkFingerprint(a, {}, std::nullopt, false).verdict, V::Untrusted);
}

TEST(TrustDecision, KnownHostsRememberPerHostAndPort) {
  QTemporaryDir temp;
  ASSERT_TRUE(temp.isValid());
  KnownHosts hosts(temp.filePath(QStringLiteral("known.ini")));
  const QByteArray a(32, '\x0a');
  EXPECT_FALSE(hosts.lookup(QStringLiteral("::1"), 47100));
  hosts.remember(QStringLiteral("::1"), 47100, a);
  hosts.remember(QStringLiteral("example.org"), 47100, QByteArray(32, '\x0b'));
  EXPECT_EQ(hosts.lookup(QStringLiteral("::1"), 47100), a);
  EXPECT_FALSE(hosts.lookup(QStringLiteral("::1"), 47101));
  EXPECT_EQ(KnownHosts(temp.filePath(QStringLiteral("known.ini"))).lookup(QStringLiteral("::1"), 47100), a);
  hosts.forget(QStringLiteral("::1"), 47100);
  EXPECT_FALSE(hosts.lookup(QStringLiteral("::1"), 47100));
  EXPECT_TRUE(hosts.lookup(QStringLiteral("example.org"), 47100));
}

}  // namespace
}  // namespace sc::session
