#pragma once
// The paper experiments and benchmarks moved to their own executable, shapecast-lab (experiments/). Their
// historical command lines keep working: `shapecast-cli experiment loss|load …` and `shapecast-cli bench table1 …`
// run the shapecast-lab next to shapecast-cli with the same arguments (it accepts these spellings), so that
// shapecast-cli itself links none of the experiments.

#include <QStringList>

#include <span>

namespace sc::app {

/// Exit code when shapecast-lab cannot be run (as a shell's for a command it cannot find).
inline constexpr int kExitLabMissing = 127;

/// Whether `arguments` (those after the program name) are a command that moved to shapecast-lab: `experiment …`
/// or `bench table1 …`.
bool isLabCommand(const QStringList& arguments);

/// Replaces this process with shapecast-lab, passing `arguments` (argv after the program name, unchanged): its
/// output, exit code and signals are then the command's own. Returns only when shapecast-lab cannot be run: prints
/// why on stderr and returns kExitLabMissing.
int runLabAlias(std::span<char* const> arguments);

}  // namespace sc::app
