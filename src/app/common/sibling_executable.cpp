#include "app/common/sibling_executable.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace sc::app {

QString siblingExecutablePath(const QString& name) {
  return QDir(QCoreApplication::applicationDirPath()).filePath(name);
}

QString execSibling(const QString& name, std::span<char* const> arguments) {
  const QString path = siblingExecutablePath(name);
  QByteArray program = QFile::encodeName(path);
  std::vector<char*> argv;
  argv.reserve(arguments.size() + 2);
  argv.push_back(program.data());
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  ::execv(program.constData(), argv.data());
  return QStringLiteral("cannot run %1: %2").arg(path, QString::fromLocal8Bit(std::strerror(errno)));
}

}  // namespace sc::app
