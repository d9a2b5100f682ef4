#include "scipy_peer_runner.h"

#include <QJsonDocument>
#include <QProcess>

namespace sc::bench {

std::optional<ScipyPython> findScipyPython(const QStringList& candidates) {
  for (const QString& candidate : candidates) {
    QProcess process;
    process.start(candidate, {QStringLiteral("-c"), QStringLiteral("import scipy; print(scipy.__version__)")});
    if (process.waitForFinished(60000) && process.exitStatus() == QProcess::NormalExit && process.exitCode() == 0)
      return ScipyPython{candidate, QString::fromLatin1(process.readAllStandardOutput()).trimmed()};
  }
  return std::nullopt;
}

std::optional<QJsonObject> runScipyPeer(const ScipyPython& python, const QString& script, const QString& folder,
                                        int timeoutMs, QString& error) {
  QProcess process;
  process.start(python.executable, {script, folder});
  if (!process.waitForFinished(timeoutMs)) {
    process.kill();
    process.waitForFinished();
    error = QStringLiteral("the SciPy peer did not finish in %1 s").arg(timeoutMs / 1000);
    return std::nullopt;
  }
  if (process.exitStatus() != QProcess::NormalExit || process.exitCode() != 0) {
    error = QStringLiteral("the SciPy peer failed: ") + QString::fromLocal8Bit(process.readAllStandardError());
    return std::nullopt;
  }
  const QList<QByteArray> lines = process.readAllStandardOutput().trimmed().split('\n');
  const QJsonDocument json = QJsonDocument::fromJson(lines.last());
  if (!json.isObject()) {
    error = QStringLiteral("the SciPy peer printed no JSON object");
    return std::nullopt;
  }
  return json.object();
}

}  // namespace sc::bench
