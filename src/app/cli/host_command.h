#pragma once
// shapecast-cli host MESH [--port P] [--udp-port U] [--password-file F] [--name N] [--mode linear|rigid]
//                         [--reference-every N] [--seconds T] [--m 100] [--no-cache] [--cache-dir DIR]
//                         [--nats URL --session ID --nats-user U (--nats-password P | --nats-password-file F)]
// Loads the mesh and its basis and hosts a session until Ctrl-C (or T seconds), printing who joined, the lock and
// every peer's reported figures. With --nats it also publishes every frame, the keyframe and the session facts to
// that NATS server for viewers (`watch`; session/net/relay_publisher.h). Exit codes: cli_common.h.

#include <QStringList>

namespace sc::app {

int runHostCommand(const QStringList& arguments);

}  // namespace sc::app
