#pragma once
// shapecast-lab: the paper experiments and benchmarks, apart from the product's shapecast-cli.
//
//   shapecast-lab loss   [--mesh MESH] [options]     the loss experiment (loss/loss_command.h)
//   shapecast-lab load   --clients N --seconds T …   the load experiment (load/load_experiment.h)
//   shapecast-lab join   [--mesh MESH] [--rate-mbit R] … the join experiment (join/join_experiment.h)
//   shapecast-lab fanout --viewers N --seconds T … the fan-out experiment through NATS (fanout/fanout_experiment.h)
//   shapecast-lab table1 [MESH…] [options]           the paper's Table 1 (table1/table1_command.h)
//
// The historical spellings `experiment loss|load|load-host …` and `bench table1 …` are accepted too:
// `shapecast-cli experiment …` and `shapecast-cli bench table1 …` run this executable with their arguments
// unchanged (app/cli/lab_alias.h), and the load experiment starts its host child as `experiment load-host`.

#include <QStringList>

namespace sc::app {

/// `--mesh MESH` (the spelling) becomes the parser's MESH positional argument, appended at the end;
/// default: the 23k dragon of the fetched meshes.
QStringList withMeshPositional(QStringList arguments);

/// Runs one lab subcommand. `arguments`: those after the program name. Unknown or missing subcommands print the
/// usage on stderr and return kExitUsage (2); --help prints it on stdout and returns 0. Returns the exit code.
int runLabCommand(QStringList arguments);

/// Whether `arguments` (after the program name) run under a QGuiApplication: the experiments (the loss
/// experiment's PNG plot needs one; load and load-host have always shared the `experiment` group's application),
/// not table1, which needs only Qt Core.
bool labCommandNeedsGui(const QStringList& arguments);

}  // namespace sc::app
