#pragma once
// The load experiment (hardening issue, item 5): `shapecast-cli experiment load --clients N --seconds T`.
//   - The host runs in a child process (`shapecast-cli experiment load-host`, runLoadHost()), so that its CPU time
//     is its own: it measures getrusage(RUSAGE_SELF) user + system time (all its threads) over the drag.
//   - N headless SessionClients run in this process on a few threads (settings.clientThreads); each asks for a
//     small level (settings.clientFraction) so that reconstruction does not starve the receive path.
//   - The host's own user plays the scripted drag (defaultLossDrag(), looped) at 30 frames per second for T s;
//     idle refreshes are off, so every datagram counted is a drag frame.
// Loss is counted at both ends: per client, the datagrams the host handed to its socket for that client (host
// counters) against those the client received (its ReceiverStatistics); the host's failed sends (socket refused:
// loss caused by the host) and the kernel's UDP receive-buffer drops (/proc/net/snmp RcvbufErrors: the client
// process read too slowly) are reported apart.
// Control of the child: it prints "load-host port P", then reads commands on stdin: "drag T" (prints "drag done"
// when the drag ended) and "report" (prints one JSON line, see runLoadHost(), and exits).

#include "app/cli/cli_common.h"

#include <QJsonObject>
#include <QString>

#include <cstdint>
#include <functional>
#include <optional>
#include <variant>
#include <vector>

namespace sc::app {

struct LoadExperimentSettings {
  int clients = 8;               ///< 1..kMaxPeers − 1
  double seconds = 10.0;         ///< drag duration
  double clientFraction = 0.05;  ///< each client's level: this fraction of the vertices
  int clientThreads = 4;         ///< client threads in this process (clients spread round-robin)
};

/// One client's figures over the drag.
struct LoadClientRow {
  int peer = 0;
  std::int64_t sentByHost = 0;  ///< datagrams the host's socket accepted for this client
  std::int64_t received = 0;    ///< distinct datagrams the client received
  std::int64_t dropped = 0;     ///< datagrams the client's assembler rejected (late, duplicate, bad tag, …)
  double lossFraction = 0.0;    ///< 1 − received / sentByHost
  double latencyP50Ms = 0.0, latencyP99Ms = 0.0;  ///< drag at the host → datagram decoded at the client
};

struct LoadResult {
  QString mesh;
  int vertices = 0, rows = 0, clientVertices = 0;
  LoadExperimentSettings settings;
  double dragSeconds = 0.0;       ///< measured by the host
  double hostCpuPercent = 0.0;    ///< host user + system time / drag wall time, % of one core
  double clientCpuPercent = 0.0;  ///< this (clients') process over the same window, % of one core
  std::int64_t frames = 0;        ///< frames the host sent during the drag
  std::int64_t datagramsSent = 0, hostSendErrors = 0;
  std::int64_t udpRcvbufErrors = 0, udpSndbufErrors = 0;  ///< kernel counters (whole machine) over the window
  double loadAverage = 0.0;  ///< the machine's 1-minute load average at the end of the drag (other work included)
  std::vector<LoadClientRow> clients;
};

/// Runs the experiment; `progress` gets one line per step. The host child is `executable` (this program).
std::variant<LoadResult, QString> runLoadExperiment(const QString& executable, const QString& meshPath,
                                                    const QStringList& basisArguments,
                                                    const LoadExperimentSettings& settings,
                                                    const std::function<void(const QString&)>& progress);

/// `shapecast-cli experiment load` (arguments after "load", MESH positional): parses, runs, prints (--json or a
/// Markdown table) and, with --markdown FILE, writes the "load-experiment" section of FILE. Returns the exit code.
int runLoadExperimentCommand(const QStringList& arguments);

/// The child role (`experiment load-host MESH --clients N [basis options]`): hosts MESH on 127.0.0.1 for N
/// clients and follows the stdin commands above (its first line also names the mesh's vertex and row counts).
/// Its report line, over the last drag: {"drag_seconds", "cpu_seconds", "frames", "send_errors", "peers":
/// [{"peer", "datagrams"}]}. Returns the exit code.
int runLoadHost(const QStringList& arguments);

/// The --json form (figures, min/median/max across clients, per-client rows) and the Markdown section.
QJsonObject loadResultJson(const LoadResult& result);
QString loadResultMarkdown(const LoadResult& result, const QString& machine);

}  // namespace sc::app
