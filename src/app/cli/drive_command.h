#pragma once
// shapecast-cli drive HOST:PORT --script DRAG.json [--name N] [--password-file F] [--json]
// Joins a session (full resolution: the script's selections are resolved on the full rest mesh), takes the edit
// lock (waiting in the queue if needed), sends the script's constraints and plays its frames at the script's frame
// rate, then releases the lock and leaves. Exit codes: cli_common.h.

#include <QStringList>

namespace sc::app {

int runDriveCommand(const QStringList& arguments);

}  // namespace sc::app
