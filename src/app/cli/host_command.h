#pragma once
// shapecast-cli host MESH [--port P] [--udp-port U] [--password-file F] [--name N] [--mode linear|rigid]
//                         [--reference-every N] [--seconds T] [--m 100] [--no-cache] [--cache-dir DIR]
// Loads the mesh and its basis and hosts a session until Ctrl-C (or T seconds), printing who joined, the lock and
// every peer's reported figures. Exit codes: cli_common.h.

#include <QStringList>

namespace sc::app {

int runHostCommand(const QStringList& arguments);

}  // namespace sc::app
