#pragma once
// shapecast-cli join HOST:PORT [--name N] [--password-file F] [--level full|N] [--loss P] [--burst L] [--seed S]
//                              [--zero-fill] [--seconds T] [--stats-json FILE] [--json]
// Joins a session headless: receives the model (or the level closest to N vertices), applies every frame, measures
// live Hausdorff distortion against the host's exact reference frames, prints its figures once a second, and at
// the end (T seconds, Ctrl-C, or the host leaving) writes them to FILE. --loss/--burst simulate a lossy network
// on receive (Bernoulli, or Gilbert–Elliott with mean burst L). Exit codes: cli_common.h.

#include <QStringList>

namespace sc::app {

int runJoinCommand(const QStringList& arguments);

}  // namespace sc::app
