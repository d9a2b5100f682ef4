#include "app/cli/lab_alias.h"

#include "app/common/sibling_executable.h"

#include <QTextStream>

namespace sc::app {

bool isLabCommand(const QStringList& arguments) {
  if (arguments.isEmpty()) return false;
  if (arguments.constFirst() == QLatin1String("experiment")) return true;
  return arguments.constFirst() == QLatin1String("bench") && arguments.size() > 1 &&
         arguments.at(1) == QLatin1String("table1");
}

int runLabAlias(std::span<char* const> arguments) {
  const QString why = execSibling(QStringLiteral("shapecast-lab"), arguments);
  QTextStream(stderr) << "shapecast-cli: the experiments and benchmarks are in shapecast-lab, next to shapecast-cli ("
                      << why << "); build the target shapecast-lab\n";
  return kExitLabMissing;
}

}  // namespace sc::app
