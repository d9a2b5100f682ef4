#pragma once
// The join experiment (issue 17 item 5): `shapecast-lab join --mesh M --rate-mbit R --delay-ms D --loss P
// [--level L] [--json]`. How long a client waits, and how much it receives, before it shows the live deformed
// shape over a link of a given rate.
//   - The host runs in a child process (`experiment load-host`, load_experiment.h) that plays the loss experiment's
//     drag in a loop from before the client joins, so every frame the client gets is a deformed one.
//   - One SessionClient runs in this process with the emulated link (session::ImpairmentSettings: rate, delay,
//     loss; the rate throttles the TLS level transfer and the datagrams alike, link_rate.h).
//   - The client joins progressively (issue 17 item 4; --no-progressive: the requested level only): the host's
//     smallest level first, then the requested one in the background.
//   - Times are from client.start() (TCP connect) to: the first level installed (first_level_s, of
//     first_level_vertices: the preview when progressive), the requested level installed (level_ready_s: the whole
//     requested level received, SHA-256 checked and decoded) and the first displayed frame that came from the host
//     after the first level (first_frame_s: a Keyframe or a datagram frame, on the preview when progressive).
//   - bytes_received: TLS plaintext read (control messages + level transfer) + datagram payloads.
//   - peak_rss_mb: this process's getrusage(RUSAGE_SELF) ru_maxrss at the end. This process holds only the client
//     (the mesh, basis and host are in the child), plus the Qt libraries and the experiment's own code;
//     baseline_rss_mb is the same figure read just before the client starts, so the client's share is the
//     difference.

#include "app/cli/cli_common.h"

#include <QJsonObject>
#include <QString>
#include <QStringList>

#include <cstdint>
#include <functional>
#include <variant>

namespace sc::app {

struct JoinExperimentSettings {
  double rateMbit = 20.0;   ///< link rate; 0 = unlimited
  int delayMs = 20;         ///< one-way delay on the datagrams
  double loss = 0.0;        ///< datagram loss ratio
  std::uint32_t level = 0;  ///< requested level in vertices (0 = full)
  double timeoutSeconds = 1800.0;
  bool progressive = true;  ///< the smallest level first (SessionClientOptions::progressive)
};

struct JoinResult {
  QString mesh;
  int vertices = 0, rows = 0;
  JoinExperimentSettings settings;
  std::uint32_t levelVertices = 0;
  std::uint64_t streamBytes = 0, datagramBytes = 0;
  double levelReadySeconds = 0.0, firstFrameSeconds = 0.0;
  double firstLevelSeconds = 0.0;  ///< the first level installed (the preview when progressive)
  std::uint32_t firstLevelVertices = 0;
  double transferMbit = 0.0;  ///< the requested level's bytes · 8 / (its last chunk − its ModelBegin), Mbit/s
  double peakRssMb = 0.0, baselineRssMb = 0.0;
  /// False when the host child refused its scripted drag (it does on the 100k dragon): no deformed frame comes,
  /// firstFrameSeconds is −1 (null in JSON) and only the level is timed.
  bool hostDrags = true;
};

/// Runs the experiment; `progress` gets one line per step. The host child is `executable` (this program).
std::variant<JoinResult, QString> runJoinExperiment(const QString& executable, const QString& meshPath,
                                                    const QStringList& basisArguments,
                                                    const JoinExperimentSettings& settings,
                                                    const std::function<void(const QString&)>& progress);

/// `shapecast-lab join` (arguments after "join", MESH positional): parses, runs, prints one line or (--json) one
/// JSON object. Returns the exit code.
int runJoinExperimentCommand(const QStringList& arguments);

/// {"mesh", "vertices", "rows", "level_vertices", "rate_mbit", "delay_ms", "loss", "bytes_received",
///  "stream_bytes", "datagram_bytes", "first_frame_s" (null without a host drag), "host_drags", "level_ready_s",
///  "first_level_s", "first_level_vertices", "progressive", "transfer_mbit", "peak_rss_mb", "baseline_rss_mb"}
QJsonObject joinResultJson(const JoinResult& result);

}  // namespace sc::app
