#include "host_process.h"

#include <QRegularExpression>

namespace sc::testing {

HostProcess::HostProcess(const QString& mesh, const QStringList& extra) {
  m_process.setProcessChannelMode(QProcess::SeparateChannels);
  m_process.start(QStringLiteral(SHAPECAST_CLI),
                  QStringList{QStringLiteral("host"), mesh, QStringLiteral("--port"), QStringLiteral("0"),
                              QStringLiteral("--no-cache"), QStringLiteral("--m"), QStringLiteral("30"),
                              QStringLiteral("--reference-every"), QStringLiteral("5")} +
                      extra);
  const QRegularExpression portLine(QStringLiteral("TCP port (\\d+)"));
  for (int i = 0; i < 600 && m_port == 0; ++i) {
    m_process.waitForReadyRead(100);
    m_output += m_process.readAllStandardOutput();
    const QRegularExpressionMatch match = portLine.match(QString::fromUtf8(m_output));
    if (match.hasMatch()) m_port = match.captured(1).toUShort();
    if (m_process.state() == QProcess::NotRunning) break;
  }
}

HostProcess::~HostProcess() {
  m_process.terminate();
  m_process.waitForFinished(10000);
}

QByteArray HostProcess::stop() {
  m_process.terminate();
  m_process.waitForFinished(10000);
  return m_output + m_process.readAllStandardOutput();
}

void HostProcess::kill() {
  m_process.kill();
  m_process.waitForFinished(10000);
}

}  // namespace sc::testing
