// The test processes' children (shapecast-cli host, join, drive…) keep their settings and data in a folder of this
// test run, never the user's: XDG_CONFIG_HOME and XDG_DATA_HOME are set for the whole test process at start-up, and
// every QProcess inherits them unless a test passes an environment of its own. The settings hold the known hosts
// (a fingerprint per host:port, trust on first use) and the data the host's TLS identity: with the user's, a
// loopback port that an earlier run's host had used with another certificate made `join` and `drive` refuse "the
// host's certificate fingerprint changed" (seen in CI on a machine that had run the suite many times), and every run
// added entries to the user's settings.

#include <QFile>
#include <QTemporaryDir>
#include <QtGlobal>

namespace sc::testing {
namespace {

[[maybe_unused]] const bool kChildrenUseAnIsolatedHome = [] {
  static QTemporaryDir home;  // removed when the test process exits
  if (!home.isValid()) return false;
  qputenv("XDG_CONFIG_HOME", QFile::encodeName(home.filePath(QStringLiteral("config"))));
  qputenv("XDG_DATA_HOME", QFile::encodeName(home.filePath(QStringLiteral("data"))));
  return true;
}();

}  // namespace
}  // namespace sc::testing
