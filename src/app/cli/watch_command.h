#pragma once
// shapecast-cli watch --nats URL --session ID --nats-user U (--nats-password P | --nats-password-file F)
//                     [--pin FINGERPRINT] [--seconds T] [--frames N] [--pending 8] [--json]
// A headless viewer of a relayed session (issue 18): subscribes through NATS without connecting to the host, joins
// from the keyframe, verifies every frame against the pinned host certificate (without --pin: trusts the first
// one and prints it), applies the newest frames to Z and prints a line of figures every second, then a summary
// (frames applied, lost, stale, bad signatures, dropped while waiting, latency p50/p99: meaningful when the host
// runs on the same machine). No level: Z alone. Exit codes: cli_common.h.

#include <QStringList>

namespace sc::app {

int runWatchCommand(const QStringList& arguments);

}  // namespace sc::app
