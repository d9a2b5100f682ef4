#pragma once
// Ctrl-C / SIGTERM for the long-running subcommands (host, join): the signal handler only writes one byte to a
// socket pair (async-signal-safe); a QSocketNotifier on the other end calls the callback in the event loop, as in
// Qt's "Calling Qt Functions From Unix Signal Handlers".

#include <functional>

namespace sc::app {

/// Installs handlers for SIGINT and SIGTERM that run `onSignal` in the Qt event loop of the calling thread (once
/// per signal). Call once per process, after the QCoreApplication exists. Returns false if the socket pair or the
/// handlers could not be set up (the command then simply cannot be stopped gracefully).
bool quitOnSignal(std::function<void()> onSignal);

}  // namespace sc::app
