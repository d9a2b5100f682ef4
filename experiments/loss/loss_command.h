#pragma once
// shapecast-lab loss [--mesh MESH] [--loss 0,0.02,0.05,0.1,0.2,0.3,0.5] [--burst [--burst-length L]] [--seed S]
//                    [--low-fraction 0.05] [--json] [--markdown FILE] [--plot FILE] [--m 100]
// (also `shapecast-cli experiment loss …`, which runs shapecast-lab.) Reproduces the paper's Figures 3 and 4 with a
// real host and real clients on loopback (loss_experiment.h), prints the rows, and writes the table and a PNG plot
// into docs/benchmarks.md. Default mesh: the 23k Stanford dragon.

#include <QStringList>

namespace sc::app {

/// Runs the loss experiment. `arguments`: those after "loss", with the mesh as the one positional argument
/// (withMeshPositional(), lab_command.h). Returns the exit code (cli_common.h).
int runLossCommand(const QStringList& arguments);

}  // namespace sc::app
