#pragma once
// Helpers of the shapecast-cli end-to-end tests: run the real executables (shapecast-cli, shapecast-lab), write
// generated meshes as OFF files.

#include "test_meshes.h"

#include <QByteArray>
#include <QProcessEnvironment>
#include <QString>
#include <QStringList>

namespace sc::testing {

/// What one run of shapecast-cli produced.
struct CliRun {
  int exitCode = -1;
  QByteArray out, err;
};

/// Runs the shapecast-cli executable (SHAPECAST_CLI) with `arguments` in `workingDirectory` (empty: this process's
/// current folder) and `environment` (empty: this process's) and waits up to two minutes for it.
CliRun runCli(const QStringList& arguments, const QString& workingDirectory = {},
              const QProcessEnvironment& environment = {});

/// Runs the shapecast-lab executable (SHAPECAST_LAB) with `arguments` and waits up to two minutes for it.
CliRun runLab(const QStringList& arguments);

/// Writes `mesh` as an ASCII OFF file with 17 significant digits.
void writeOff(const QString& path, const GeneratedMesh& mesh);

}  // namespace sc::testing
