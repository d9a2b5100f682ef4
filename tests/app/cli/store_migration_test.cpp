// shapecast-cli shares the desktop app's store of known hosts and host identity: a real run of the executable
// with a home that holds only the store it used before (organisation "Unknown Organization") moves it over.

#include "cli_test_support.h"

#include <gtest/gtest.h>
#include <QDir>
#include <QFile>
#include <QProcessEnvironment>
#include <QSettings>
#include <QTemporaryDir>

namespace sc::testing {
namespace {

TEST(StoreMigration, TheCliMovesItsFormerKnownHostsAndIdentityIntoTheDesktopAppsStoreOnce) {
  QTemporaryDir home;
  ASSERT_TRUE(home.isValid());
  const QString config = home.filePath(QStringLiteral("config"));
  const QString data = home.filePath(QStringLiteral("data"));
  {
    QSettings old(config + QStringLiteral("/Unknown Organization/shapecast.conf"), QSettings::IniFormat);
    old.setValue(QStringLiteral("knownHosts/studio.example:7001"), QStringLiteral("AB:CD"));
  }
  const QString oldIdentity = data + QStringLiteral("/shapecast/tls");
  ASSERT_TRUE(QDir().mkpath(oldIdentity));
  for (const char* name : {"host-key.pem", "host-cert.pem"}) {
    QFile file(QDir(oldIdentity).filePath(QLatin1String(name)));
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(QByteArray("contents of ") + name);
  }
  QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
  environment.insert(QStringLiteral("XDG_CONFIG_HOME"), config);
  environment.insert(QStringLiteral("XDG_DATA_HOME"), data);
  const QString mesh = home.filePath(QStringLiteral("torus.off"));
  writeOff(mesh, torus(24, 12));

  const CliRun first = runCli({QStringLiteral("basis"), mesh, QStringLiteral("-m"), QStringLiteral("8"),
                               QStringLiteral("--no-cache"), QStringLiteral("--json")},
                              {}, environment);
  ASSERT_EQ(first.exitCode, 0) << first.err.constData();
  EXPECT_TRUE(first.err.contains("1 known host(s) of shapecast-cli's former store")) << first.err.constData();
  const QString shared = config + QStringLiteral("/ShapeCast/shapecast.conf");
  EXPECT_EQ(QSettings(shared, QSettings::IniFormat).value(QStringLiteral("knownHosts/studio.example:7001")).toString(),
            QStringLiteral("AB:CD"));
  QFile certificate(data + QStringLiteral("/ShapeCast/shapecast/tls/host-cert.pem"));
  ASSERT_TRUE(certificate.open(QIODevice::ReadOnly)) << "the identity is where the desktop app's host looks";
  EXPECT_EQ(certificate.readAll(), QByteArray("contents of host-cert.pem"));

  QSettings(shared, QSettings::IniFormat).remove(QStringLiteral("knownHosts/studio.example:7001"));  // forgotten
  const CliRun second = runCli({QStringLiteral("basis"), mesh, QStringLiteral("-m"), QStringLiteral("8"),
                                QStringLiteral("--no-cache"), QStringLiteral("--json")},
                               {}, environment);
  ASSERT_EQ(second.exitCode, 0) << second.err.constData();
  EXPECT_FALSE(second.err.contains("former store")) << "said once, not on every run";
  EXPECT_FALSE(QSettings(shared, QSettings::IniFormat).contains(QStringLiteral("knownHosts/studio.example:7001")))
      << "a host forgotten after the migration stays forgotten";
}

}  // namespace
}  // namespace sc::testing
