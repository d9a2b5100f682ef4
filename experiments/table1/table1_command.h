#pragma once
// `shapecast-cli bench table1 [MESH…] [--m 100] [--low-fraction 0.05] [--frames 200] [--json] [--markdown FILE]`

#include <QStringList>

namespace sc::app {

/// Reproduces the paper's Table 1 on this machine for each mesh (default: the fetched lion, Chinese dragon and the
/// 23k and 100k Stanford dragons): sizes at full and low resolution, pre-computing time, server and client time per
/// frame. Prints a table with the paper's own rows beside ours (or, with --json, a JSON list with one object per
/// mesh) and writes the table into docs/benchmarks.md (section "table1") unless --markdown "" is given.
/// @param arguments  the arguments after "bench table1".
/// @return 0 ok, 1 a mesh could not be loaded, 2 bad usage, 3 a basis could not be computed.
int runTable1Command(const QStringList& arguments);

}  // namespace sc::app
