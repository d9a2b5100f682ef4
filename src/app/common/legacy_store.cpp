#include "app/common/legacy_store.h"

#include "session/net/tls_identity.h"
#include "session/net/tls_known_hosts.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QSettings>
#include <QStandardPaths>
#include <QStringList>

#include <algorithm>
#include <cstdio>

namespace sc::app {
namespace {

const QString kMigratedKey = QStringLiteral("migrations/legacyCommandLineStore");
const QStringList kIdentityFiles{session::tlsIdentityFiles().key, session::tlsIdentityFiles().certificate};

/// How many of the identity's two files `directory` holds.
int identityFileCount(const QString& directory) {
  const QDir folder(directory);
  return static_cast<int>(std::count_if(kIdentityFiles.begin(), kIdentityFiles.end(),
                                        [&folder](const QString& file) { return folder.exists(file); }));
}

QByteArray certificate(const QString& directory) {
  QFile file(QDir(directory).filePath(session::tlsIdentityFiles().certificate));
  return file.open(QIODevice::ReadOnly) ? file.readAll() : QByteArray();
}

bool sameCertificate(const QString& a, const QString& b) { return certificate(a) == certificate(b); }

/// Copies the identity's files into a new folder beside `to` (0700, each file 0600, as tls_identity.cpp writes them),
/// then renames it to `to` (absent or empty), so that `to` holds the whole identity or nothing. Returns whether it
/// does; a failed copy is removed.
bool copyIdentity(const QString& from, const QString& to) {
  const QString staging = to + QStringLiteral(".migrating");
  QDir(staging).removeRecursively();
  bool copied =
      QDir().mkpath(staging) &&
      QFile::setPermissions(staging, QFileDevice::ReadOwner | QFileDevice::WriteOwner | QFileDevice::ExeOwner);
  for (const QString& file : kIdentityFiles) {
    const QString target = QDir(staging).filePath(file);
    copied = copied && QFile::copy(QDir(from).filePath(file), target) &&
             QFile::setPermissions(target, QFileDevice::ReadOwner | QFileDevice::WriteOwner);
  }
  copied = copied && (!QDir(to).exists() || QDir().rmdir(to)) && QDir().rename(staging, to);
  if (!copied) QDir(staging).removeRecursively();
  return copied;
}

void copyHosts(QSettings& legacy, QSettings& current, LegacyStoreMigration& result) {
  legacy.beginGroup(session::KnownHosts::settingsGroup());
  current.beginGroup(session::KnownHosts::settingsGroup());
  for (const QString& host : legacy.childKeys()) {
    const QVariant fingerprint = legacy.value(host);
    if (!current.contains(host)) {
      current.setValue(host, fingerprint);
      ++result.hostsCopied;
    } else if (current.value(host) != fingerprint) {
      ++result.hostsKept;
    }
  }
  current.endGroup();
  legacy.endGroup();
}

}  // namespace

QString LegacyStoreMigration::notice() const {
  QStringList parts;
  if (hostsCopied > 0)
    parts << QStringLiteral("%1 known host(s) of shapecast-cli's former store are now shared with the desktop app.")
                 .arg(hostsCopied);
  if (hostsKept > 0)
    parts << QStringLiteral("%1 host(s) known to both with different fingerprints keep the desktop app's fingerprint.")
                 .arg(hostsKept);
  if (identityReplaced)
    parts << QStringLiteral(
                 "shapecast-cli host now shows the shared store's certificate; clients that trusted the command line's "
                 "former one are told once that the fingerprint changed (it is kept in %1).")
                 .arg(legacyIdentityDirectory);
  if (identityFailed)
    parts << QStringLiteral(
                 "The host certificate in %1 could not be copied into the shared store (tried again on the "
                 "next run).")
                 .arg(legacyIdentityDirectory);
  if (settingsFailed)
    parts << QStringLiteral("The shared settings file could not be written, so this is tried again on the next run.");
  return parts.join(QLatin1Char(' '));
}

LegacyStoreMigration migrateLegacyStore(const StoreLocations& legacy, const StoreLocations& current) {
  LegacyStoreMigration result;
  QSettings settings(current.settingsFile, QSettings::IniFormat);
  if (settings.value(kMigratedKey).toBool()) return result;
  result.ran = true;
  if (QFile::exists(legacy.settingsFile)) {
    QSettings old(legacy.settingsFile, QSettings::IniFormat);
    copyHosts(old, settings, result);
  }
  result.legacyIdentityDirectory = legacy.identityDirectory;
  const int whole = static_cast<int>(kIdentityFiles.size());
  if (identityFileCount(legacy.identityDirectory) == whole) {
    const int present = identityFileCount(current.identityDirectory);
    if (present == 0) {
      result.identityCopied = copyIdentity(legacy.identityDirectory, current.identityDirectory);
      result.identityFailed = !result.identityCopied;
    } else if (present == whole) {  // a half-written one is left for the host to report
      result.identityReplaced = !sameCertificate(legacy.identityDirectory, current.identityDirectory);
    }
  }
  if (!result.identityFailed) settings.setValue(kMigratedKey, true);  // else tried again on the next run
  settings.sync();
  result.settingsFailed = settings.status() != QSettings::NoError;
  return result;
}

StoreLocations legacyCommandLineStore() {
  const QString config = QStandardPaths::writableLocation(QStandardPaths::GenericConfigLocation);
  const QString data = QStandardPaths::writableLocation(QStandardPaths::GenericDataLocation);
  return {QDir(config).filePath(QStringLiteral("Unknown Organization/shapecast.conf")),
          QDir(data).filePath(QStringLiteral("shapecast/tls"))};
}

void nameApplication(const QString& version) {
  QCoreApplication::setOrganizationName(QStringLiteral("ShapeCast"));
  QCoreApplication::setApplicationName(QStringLiteral("shapecast"));
  QCoreApplication::setApplicationVersion(version);
}

void migrateLegacyStoreIntoThisOne(const QString& identityDirectory) {
  const LegacyStoreMigration migration =
      migrateLegacyStore(legacyCommandLineStore(), {QSettings().fileName(), identityDirectory});
  if (const QString notice = migration.notice(); !notice.isEmpty())
    std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(notice));
}

}  // namespace sc::app
