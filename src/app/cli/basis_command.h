#pragma once
// `shapecast-cli basis MESH [--m 100] [--no-cache] [--cache-dir DIR] [--json]`

#include <QStringList>

namespace sc::app {

/// Runs the basis subcommand: loads and cleans MESH, computes (or loads from the cache) its manifold harmonic
/// basis and prints the figures, as text or as one JSON object on stdout. Errors go to stderr.
/// @param arguments  the arguments after "basis".
/// @return exit code: 0 ok, 1 the mesh could not be loaded, 2 bad usage, 3 the basis could not be computed.
int runBasisCommand(const QStringList& arguments);

}  // namespace sc::app
