// The migration of shapecast-cli's former store (known hosts, host identity) into the one both executables share.

#include "app/common/legacy_store.h"

#include <gtest/gtest.h>
#include <QDir>
#include <QFile>
#include <QSettings>
#include <QTemporaryDir>

namespace sc::app {
namespace {

constexpr const char* kOldFingerprint = "AA:AA";
constexpr const char* kNewFingerprint = "BB:BB";

class LegacyStoreTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(m_dir.isValid()); }

  StoreLocations legacy() const { return {m_dir.filePath(QStringLiteral("old.conf")), m_dir.filePath("old-tls")}; }
  StoreLocations current() const { return {m_dir.filePath(QStringLiteral("new.conf")), m_dir.filePath("new-tls")}; }

  static void setHost(const QString& file, const QString& host, const char* fingerprint) {
    QSettings settings(file, QSettings::IniFormat);
    settings.setValue(QStringLiteral("knownHosts/") + host, QString::fromLatin1(fingerprint));
  }
  static QString host(const QString& file, const QString& name) {
    return QSettings(file, QSettings::IniFormat).value(QStringLiteral("knownHosts/") + name).toString();
  }
  static void writeIdentity(const QString& directory, const QByteArray& certificate) {
    ASSERT_TRUE(QDir().mkpath(directory));
    const QByteArray key = QByteArray("key of ") + certificate;
    for (const auto& [name, bytes] : {std::pair{"host-key.pem", key}, std::pair{"host-cert.pem", certificate}}) {
      QFile file(QDir(directory).filePath(QLatin1String(name)));
      ASSERT_TRUE(file.open(QIODevice::WriteOnly));
      file.write(bytes);
    }
  }
  static QByteArray read(const QString& file) {
    QFile f(file);
    return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
  }

  QTemporaryDir m_dir;
};

TEST_F(LegacyStoreTest, CopiesMissingHostsAndTheIdentityOnceAndLeavesTheLegacyStoreAsItWas) {
  setHost(legacy().settingsFile, QStringLiteral("a.example:7001"), kOldFingerprint);
  setHost(legacy().settingsFile, QStringLiteral("b.example:7001"), kOldFingerprint);
  setHost(current().settingsFile, QStringLiteral("b.example:7001"), kNewFingerprint);
  setHost(current().settingsFile, QStringLiteral("c.example:7001"), kNewFingerprint);
  writeIdentity(legacy().identityDirectory, "old certificate");
  const QByteArray legacyBytes = read(legacy().settingsFile);

  const LegacyStoreMigration first = migrateLegacyStore(legacy(), current());
  EXPECT_TRUE(first.ran);
  EXPECT_EQ(first.hostsCopied, 1);
  EXPECT_EQ(first.hostsKept, 1);
  EXPECT_TRUE(first.identityCopied);
  EXPECT_FALSE(first.identityReplaced);
  EXPECT_EQ(host(current().settingsFile, QStringLiteral("a.example:7001")), QLatin1String(kOldFingerprint));
  EXPECT_EQ(host(current().settingsFile, QStringLiteral("b.example:7001")), QLatin1String(kNewFingerprint));
  EXPECT_EQ(host(current().settingsFile, QStringLiteral("c.example:7001")), QLatin1String(kNewFingerprint));
  const QString key = QDir(current().identityDirectory).filePath(QStringLiteral("host-key.pem"));
  EXPECT_EQ(read(key), QByteArray("key of old certificate"));
  EXPECT_EQ(QFile::permissions(key) & (QFileDevice::ReadGroup | QFileDevice::ReadOther), QFileDevice::Permissions{});
  EXPECT_EQ(read(legacy().settingsFile), legacyBytes);
  EXPECT_TRUE(first.notice().contains(QLatin1String("1 known host")));

  // a host forgotten after the migration stays forgotten
  QSettings(current().settingsFile, QSettings::IniFormat).remove(QStringLiteral("knownHosts/a.example:7001"));
  const LegacyStoreMigration second = migrateLegacyStore(legacy(), current());
  EXPECT_FALSE(second.ran);
  EXPECT_TRUE(host(current().settingsFile, QStringLiteral("a.example:7001")).isEmpty());
  EXPECT_TRUE(second.notice().isEmpty());
}

TEST_F(LegacyStoreTest, WhenBothHaveAnIdentityTheCurrentOneStaysAndTheUserIsTold) {
  writeIdentity(legacy().identityDirectory, "old certificate");
  writeIdentity(current().identityDirectory, "desktop certificate");
  const LegacyStoreMigration migration = migrateLegacyStore(legacy(), current());
  EXPECT_FALSE(migration.identityCopied);
  EXPECT_TRUE(migration.identityReplaced);
  EXPECT_EQ(read(QDir(current().identityDirectory).filePath(QStringLiteral("host-cert.pem"))),
            QByteArray("desktop certificate"));
  EXPECT_TRUE(migration.notice().contains(QLatin1String("certificate")));
}

TEST_F(LegacyStoreTest, AnIdentityThatCannotBeCopiedLeavesNothingBehindAndIsTriedAgain) {
  ASSERT_TRUE(QDir().mkpath(legacy().identityDirectory + QStringLiteral("/host-cert.pem")));  // a folder: unreadable
  QFile key(QDir(legacy().identityDirectory).filePath(QStringLiteral("host-key.pem")));
  ASSERT_TRUE(key.open(QIODevice::WriteOnly));
  key.write("key");
  key.close();
  const LegacyStoreMigration migration = migrateLegacyStore(legacy(), current());
  EXPECT_TRUE(migration.identityFailed);
  EXPECT_FALSE(migration.identityCopied);
  EXPECT_FALSE(QDir(current().identityDirectory).exists(QStringLiteral("host-key.pem"))) << "half an identity";
  EXPECT_FALSE(QDir(current().identityDirectory + QStringLiteral(".migrating")).exists());
  EXPECT_TRUE(migration.notice().contains(QLatin1String("could not be copied")));
  EXPECT_TRUE(migrateLegacyStore(legacy(), current()).ran) << "not recorded, so tried again";
}

TEST_F(LegacyStoreTest, WithoutALegacyStoreNothingIsCopiedAndNothingIsSaid) {
  const LegacyStoreMigration migration = migrateLegacyStore(legacy(), current());
  EXPECT_TRUE(migration.ran);
  EXPECT_EQ(migration.hostsCopied, 0);
  EXPECT_FALSE(migration.identityCopied);
  EXPECT_FALSE(migration.identityReplaced);
  EXPECT_TRUE(migration.notice().isEmpty());
  EXPECT_FALSE(QDir(current().identityDirectory).exists());
  EXPECT_FALSE(migrateLegacyStore(legacy(), current()).ran) << "the migration is recorded even when it found nothing";
}

}  // namespace
}  // namespace sc::app
