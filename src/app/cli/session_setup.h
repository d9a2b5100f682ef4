#pragma once
// What the session subcommands (host, join, drive, experiment) share: building a host's model from a mesh file,
// the client options common to join and drive, and waiting on a client from a command's event loop.

#include "app/cli/cli_common.h"
#include "app/cli/drag_script.h"
#include "session/engine/host_model.h"
#include "session/net/session_client.h"

#include <QString>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

namespace sc::app {

/// Loads and cleans the mesh, computes (or loads) its basis with the command's basis options, and packs both into
/// a HostModel. Failures are printed through `command.error()`; `exitCode` is set to kExitMeshError or
/// kExitBasisError then. Cost: loadMesh() plus basisForMesh().
std::shared_ptr<const session::HostModel> loadHostModel(const SubcommandParser& command, const QString& meshPath,
                                                        int& exitCode);

/// Runs the event loop until `done()` holds (checked whenever an event was processed, at least every 10 ms) or
/// `timeout` passed. Returns done(). For the command's own sequential steps (join, wait for a level, …).
bool waitUntil(const std::function<bool()>& done, std::chrono::milliseconds timeout);

/// How long a client waits for its first level, from its start, once the Welcome has told the session's shape (n
/// vertices, m rows): `floor` up to n·m = 10⁷ (the 100k dragon at m = 100, the size the floors were set for), and
/// proportionally longer above, since the host builds, compresses and sends the full level, and the client decodes
/// it, in time ∝ n·m (1M vertices at m = 100: 10 × floor). O(1).
[[nodiscard]] std::chrono::milliseconds levelWaitTimeout(std::uint32_t vertices, std::uint16_t rows,
                                                         std::chrono::milliseconds floor);

/// Starts `client` and waits until it is Ready (a level is displayed) or failed/left/timed out (`timeout` until the
/// Welcome, then levelWaitTimeout(n, m, timeout) from the start); on failure prints the client's reason through
/// `command.error()`. Returns true when Ready.
bool joinAndWait(const SubcommandParser& command, session::SessionClient& client, std::chrono::milliseconds timeout);

/// A constraint set as the Constraints message carries it: full-resolution vertex ids per handle group, anchors.
struct WireConstraints {
  std::vector<std::vector<std::uint32_t>> groups;
  std::vector<std::uint32_t> anchors;
};
WireConstraints wireConstraints(const spectral::ConstraintSet& constraints);

/// Sends the script's frames as drags at its frame rate, each at its scheduled time (a late timer does not shift
/// the rest), one pose for all `groups` handle groups; stops early if the client loses the lock. The event loop
/// runs meanwhile. Returns the number of drags the client accepted to send. Cost: the script's duration.
int playDragScript(session::SessionClient& client, const DragScript& script, std::size_t groups, double diagonal);

}  // namespace sc::app
