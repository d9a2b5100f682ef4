#include "cli_test_support.h"

#include <gtest/gtest.h>
#include <QProcess>

#include <fstream>

namespace sc::testing {

namespace {

CliRun runProgram(const QString& program, const QStringList& arguments, const QString& workingDirectory,
                  const QProcessEnvironment& environment = {}) {
  QProcess process;
  if (!workingDirectory.isEmpty()) process.setWorkingDirectory(workingDirectory);
  if (!environment.isEmpty()) process.setProcessEnvironment(environment);
  process.start(program, arguments);
  EXPECT_TRUE(process.waitForFinished(120000));
  return {process.exitCode(), process.readAllStandardOutput(), process.readAllStandardError()};
}

}  // namespace

CliRun runCli(const QStringList& arguments, const QString& workingDirectory, const QProcessEnvironment& environment) {
  return runProgram(QStringLiteral(SHAPECAST_CLI), arguments, workingDirectory, environment);
}

CliRun runLab(const QStringList& arguments) { return runProgram(QStringLiteral(SHAPECAST_LAB), arguments, {}); }

void writeOff(const QString& path, const GeneratedMesh& mesh) {
  std::ofstream out(path.toStdString());
  out << "OFF\n" << mesh.V.rows() << ' ' << mesh.F.rows() << " 0\n";
  out.precision(17);
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    out << mesh.V(i, 0) << ' ' << mesh.V(i, 1) << ' ' << mesh.V(i, 2) << '\n';
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    out << "3 " << mesh.F(f, 0) << ' ' << mesh.F(f, 1) << ' ' << mesh.F(f, 2) << '\n';
}

}  // namespace sc::testing
