#pragma once
// The fan-out experiment (issue 18 item 5): `shapecast-lab fanout --viewers N --seconds T [--mesh M] [--json]`.
// One host, a local nats-server and N headless relay viewers on this machine:
//   - the server: session::LocalNatsServer (generated configuration, loopback, stopped by its PID); its CPU over the
//     drag is read from /proc/<pid>/stat (utime + stime);
//   - the host: the load experiment's child (`experiment load-host … --nats URL --session fanout …`,
//     load_experiment.h) that relays through the server and plays the scripted drag at 30 fps for T s; it measures
//     its own CPU (getrusage, every thread, cnats' included) and what it published: the publisher's frames and the
//     NATS connection's out-bytes (natsConnection_GetStats: frames, keyframes and its statistics subscription's
//     protocol, payload bytes);
//   - the viewers: P = ceil(N / viewersPerProcess) child processes (`fanout-viewers`, runFanoutViewers()), each
//     holding its share of RelayViewers. In a process every viewer has its own NATS connection and subscription
//     (cnats starts a read thread and a flush thread per connection and a delivery thread per subscription), and
//     all of them verify, decode and apply on that process's one Qt thread. Each viewer verifies every frame's
//     signature itself (nothing is shared between viewers but the process, its Qt thread and the CPU), unless
//     sharedVerification: then the viewers of a process verify each message once between them
//     (session::RelayVerifiedMessages: ≈ 55 µs per viewer and frame saved, which 1,000 viewers at 30 fps on two
//     cores cannot afford), still each decoding and applying every frame.
// Counting: the viewers mark their counters before the drag starts; the host counts from the drag's start; 1 s
// after the drag (the trailing frames delivered) the host then the viewers report. A viewer's delivered fraction is
// (frames it applied since the mark) / (frames the host published since the drag started): a frame dropped
// because it waited behind newer ones (pending limit) counts as not delivered. Latency is the host stamp's age when
// the viewer applied the frame (one clock: same machine), each viewer's p50/p99 over its last 10 s; the report gives
// the distribution of those over the viewers.

#include "app/cli/cli_common.h"

#include <QJsonObject>
#include <QString>
#include <QStringList>

#include <cstdint>
#include <functional>
#include <variant>
#include <vector>

namespace sc::app {

struct FanoutExperimentSettings {
  int viewers = 10;                    ///< 1..10,000
  double seconds = 10.0;               ///< drag duration
  int viewersPerProcess = 100;         ///< viewers sharing one child process (and its Qt thread)
  int pendingLimit = 8;                ///< each viewer's pending limit (RelayViewerOptions::pendingLimit)
  bool sharedVerification = false;     ///< the viewers of a process verify each message once between them
  double startTimeoutSeconds = 120.0;  ///< for every viewer to have joined
};

/// One viewer's figures over the drag.
struct FanoutViewerRow {
  std::int64_t applied = 0, lost = 0, droppedPending = 0, badSignature = 0;
  double latencyP50Ms = 0.0, latencyP99Ms = 0.0;
};

/// One viewer process.
struct FanoutProcessRow {
  int viewers = 0;
  int threads = 0;          ///< /proc/self/status Threads at the report
  double cpuPercent = 0.0;  ///< user + system over the drag window, % of one core
  double rssMb = 0.0;       ///< resident set at the report
};

struct FanoutResult {
  QString mesh;
  int vertices = 0, rows = 0;
  FanoutExperimentSettings settings;
  double dragSeconds = 0.0;
  double hostCpuPercent = 0.0;    ///< host child's CPU over the drag, % of one core
  double serverCpuPercent = 0.0;  ///< nats-server's CPU over the same window, % of one core
  std::int64_t framesPublished = 0, keyframes = 0, publishFailures = 0;
  std::int64_t hostOutBytes = 0, hostPayloadBytes = 0;
  int audienceViewers = 0;   ///< viewers the host's aggregate counted (statistics back, item 3)
  double joinSeconds = 0.0;  ///< from starting the viewer processes to every viewer joined
  double loadAverage = 0.0;  ///< the machine's 1-minute load average at the end of the drag
  std::vector<FanoutViewerRow> viewers;
  std::vector<FanoutProcessRow> processes;
};

/// Runs the experiment; `progress` gets one line per step. The host and viewer children are `executable`.
std::variant<FanoutResult, QString> runFanoutExperiment(const QString& executable, const QString& meshPath,
                                                        const QStringList& basisArguments,
                                                        const FanoutExperimentSettings& settings,
                                                        const std::function<void(const QString&)>& progress);

/// `shapecast-lab fanout` (arguments after "fanout", MESH positional). Returns the exit code.
int runFanoutExperimentCommand(const QStringList& arguments);

/// The viewer child (`fanout-viewers --viewers K --nats URL --session ID --nats-user U --nats-password-file F
/// --pin FP [--pending N] [--shared-verify]`): starts K RelayViewers, prints "fanout-viewers ready K", then follows
/// stdin: "mark" (counters zeroed for the report, prints "marked") and "report" (prints one JSON line and exits):
/// {"threads", "cpu_seconds" (since the mark), "wall_seconds", "rss_mb", "viewers": [{"applied", "lost",
/// "dropped_pending", "bad_signature", "latency_p50_ms", "latency_p99_ms"}]}.
int runFanoutViewers(const QStringList& arguments);

/// {"viewers", "processes", "viewers_per_process", "seconds", "frames_published", "min_delivered_fraction",
///  "median_delivered_fraction", "max_lost", "latency_p50_ms" (median over viewers of their p50),
///  "latency_p99_ms" (max over viewers of their p99), "latency_p99_ms_median", "host_cpu_pct", "server_cpu_pct",
///  "host_upload_bytes_per_frame" (the host connection's out-bytes / frames published), "host_payload_bytes_per_frame",
///  "viewer_process_cpu_pct" (sum), "viewer_threads" (sum), "audience_viewers", "join_s", "load_average", …}
QJsonObject fanoutResultJson(const FanoutResult& result);

}  // namespace sc::app
