#pragma once
// The load-host child process (load_experiment.h) seen from its parent: started, read line by line, given
// commands on stdin. Shared by the load and join experiments.

#include "app/cli/cli_common.h"
#include "app/cli/session_setup.h"

#include <QProcess>
#include <QString>
#include <QStringList>

#include <QTextStream>

#include <chrono>
#include <functional>

namespace sc::app {

/// The basis options a host child starts with, from the experiment's own: --m M, then --cache-dir DIR or --no-cache.
inline QStringList hostChildBasisArguments(const BasisArguments& basis) {
  QStringList arguments{QStringLiteral("--m"), QString::number(basis.m)};
  if (basis.cacheDir) {
    arguments << QStringLiteral("--cache-dir") << QString::fromStdString(basis.cacheDir->string());
  } else {
    arguments << QStringLiteral("--no-cache");
  }
  return arguments;
}

/// An experiment's progress lines: on stderr, or nowhere when the report is JSON (stdout stays one object).
inline std::function<void(const QString&)> progressPrinter(bool json) {
  return [json](const QString& line) {
    if (!json) QTextStream(stderr) << line << '\n';
  };
}

/// The host child: started, and read line by line; closed (stdin) and reaped by the destructor.
class HostChild {
 public:
  bool start(const QString& executable, const QStringList& arguments) {
    m_process.setProcessChannelMode(QProcess::ForwardedErrorChannel);
    m_process.start(executable, arguments);
    return m_process.waitForStarted();
  }
  /// Waits for a stdout line starting with `prefix`; returns it (empty after `timeout` or if the child ended). Lines
  /// before it are skipped; lines after it are left for the next call.
  QString waitLine(const QString& prefix, std::chrono::milliseconds timeout) {
    QString found;
    waitUntil(
        [&] {
          while (found.isEmpty() && m_process.canReadLine()) {  // the lines after it stay for the next wait
            const QString line = QString::fromUtf8(m_process.readLine()).trimmed();
            if (line.startsWith(prefix)) found = line;
          }
          return !found.isEmpty() || m_process.state() == QProcess::NotRunning;
        },
        timeout);
    return found;
  }
  void command(const QByteArray& line) { m_process.write(line + '\n'); }
  ~HostChild() {
    m_process.closeWriteChannel();
    if (!m_process.waitForFinished(5000)) m_process.kill();
    m_process.waitForFinished(5000);
  }

 private:
  QProcess m_process;
};

}  // namespace sc::app
