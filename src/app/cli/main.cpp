// shapecast-cli: headless ShapeCast tool. Usage: shapecast-cli <subcommand> [options]; see --help.

#include "app/cli/basis_command.h"
#include "app/cli/deform_command.h"
#include "app/cli/table1_command.h"

#include <QCoreApplication>
#include <QTextStream>

namespace {

constexpr const char* kUsage =
    "usage: shapecast-cli <subcommand> [options]\n"
    "\n"
    "subcommands:\n"
    "  basis MESH [--m 100] [--no-cache] [--cache-dir DIR] [--json]\n"
    "      compute (or load from the cache) the manifold harmonic basis of MESH and print its figures\n"
    "  deform MESH --script DRAG.json [--mode linear|rigid] [--level N] [--out FILE] [--m 100] [--no-cache]\n"
    "         [--cache-dir DIR] [--json]\n"
    "      replay a drag script (docs/drag-script.md) with the spectral deformer and write the deformed mesh\n"
    "  bench table1 [MESH...] [--m 100] [--low-fraction 0.05] [--frames 200] [--json] [--markdown FILE]\n"
    "      reproduce the paper's Table 1 on this machine and write it to docs/benchmarks.md\n"
    "\n"
    "run 'shapecast-cli <subcommand> --help' for the options of a subcommand\n";

}  // namespace

int main(int argc, char* argv[]) {
  QCoreApplication app(argc, argv);
  QCoreApplication::setApplicationName(QStringLiteral("shapecast"));
  QCoreApplication::setApplicationVersion(QStringLiteral(SHAPECAST_VERSION));
  QStringList arguments = QCoreApplication::arguments();
  arguments.removeFirst();
  const QString subcommand = arguments.isEmpty() ? QString() : arguments.takeFirst();
  if (subcommand == QLatin1String("basis")) return sc::app::runBasisCommand(arguments);
  if (subcommand == QLatin1String("deform")) return sc::app::runDeformCommand(arguments);
  if (subcommand == QLatin1String("bench") && !arguments.isEmpty() && arguments.constFirst() == QLatin1String("table1"))
    return sc::app::runTable1Command(arguments.mid(1));

  QTextStream err(stderr);
  if (subcommand.isEmpty() || subcommand == QLatin1String("--help") || subcommand == QLatin1String("-h")) {
    QTextStream(stdout) << kUsage;
    return subcommand.isEmpty() ? 2 : 0;
  }
  err << "shapecast-cli: unknown subcommand '" << subcommand << "'\n\n" << kUsage;
  return 2;
}
