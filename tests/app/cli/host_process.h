#pragma once
// A running `shapecast-cli host` for the end-to-end tests: started on a mesh with port 0, its TCP port read from
// its first lines; stopped gracefully (SIGTERM), killed (SIGKILL) or frozen (SIGSTOP) on demand.

#include <QByteArray>
#include <QProcess>
#include <QString>
#include <QStringList>

namespace sc::testing {

class HostProcess {
 public:
  /// Starts `shapecast-cli host MESH --port 0 --no-cache --m 30 --reference-every 5 EXTRA…` and waits (up to a
  /// minute) for the line that names its TCP port; port() is 0 if none came.
  explicit HostProcess(const QString& mesh, const QStringList& extra = {});
  /// Stops the host (SIGTERM) if it still runs.
  ~HostProcess();
  HostProcess(const HostProcess&) = delete;
  HostProcess& operator=(const HostProcess&) = delete;

  quint16 port() const { return m_port; }
  QString address() const { return QStringLiteral("127.0.0.1:%1").arg(m_port); }
  /// Stops the host (SIGTERM, graceful) and returns everything it printed.
  QByteArray stop();
  /// Kills the host (SIGKILL: no Leave, the kernel closes its sockets) and waits for it to end.
  void kill();
  int exitCode() const { return m_process.exitCode(); }

 private:
  QProcess m_process;
  QByteArray m_output;
  quint16 m_port = 0;
};

}  // namespace sc::testing
