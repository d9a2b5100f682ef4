#pragma once
// Compatibility aliases between the executables of one build: a command that moved to another executable (e.g.
// `shapecast-cli experiment loss`, now shapecast-lab's) keeps working by running that executable, which lies in the
// same folder (build/bin, or wherever they are installed together).

#include <QString>

#include <span>

namespace sc::app {

/// The path of `name` next to this process's executable (QCoreApplication::applicationDirPath(); needs a
/// QCoreApplication).
QString siblingExecutablePath(const QString& name);

/// Replaces this process with the executable `name` next to it (execv), passing `arguments` (those after the
/// program name, as this process received them) unchanged; stdin, stdout, stderr, the environment, signals and
/// the exit code are then the other program's own. Flushes the C streams first.
/// Returns only when the program cannot be run: a readable reason naming its path.
QString execSibling(const QString& name, std::span<char* const> arguments);

}  // namespace sc::app
