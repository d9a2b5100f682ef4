#include "experiments/report/machine_info.h"

#include <QFile>
#include <QRegularExpression>
#include <QSysInfo>
#include <QThread>

namespace sc::report {
namespace {

/// The first value of "key : value" in a /proc file, or an empty string.
QString procValue(const QString& file, const QString& key) {
  QFile f(file);
  if (!f.open(QIODevice::ReadOnly | QIODevice::Text)) return {};
  const QRegularExpression pattern(
      QStringLiteral("^") + QRegularExpression::escape(key) + QStringLiteral("\\s*:\\s*(.*)$"),
      QRegularExpression::MultilineOption);
  const QRegularExpressionMatch match = pattern.match(QString::fromLocal8Bit(f.readAll()));
  return match.hasMatch() ? match.captured(1).trimmed() : QString();
}

}  // namespace

QString machineDescription() {
  const double memoryKiB =
      procValue(QStringLiteral("/proc/meminfo"), QStringLiteral("MemTotal")).section(QLatin1Char(' '), 0, 0).toDouble();
  return QStringLiteral("%1, %2 logical cores, %3 GiB RAM, %4 %5")
      .arg(procValue(QStringLiteral("/proc/cpuinfo"), QStringLiteral("model name")))
      .arg(QThread::idealThreadCount())
      .arg(memoryKiB / (1024.0 * 1024.0), 0, 'f', 1)
      .arg(QSysInfo::kernelType(), QSysInfo::kernelVersion());
}

}  // namespace sc::report
