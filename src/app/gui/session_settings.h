#pragma once
// The plain values a session window exchanges with its controllers (session_controller.h): what hosting and
// joining need (HostSettings, JoinSettings), a client's emulated network conditions, how a host's certificate was
// trusted, the host user's deformer state (what undo/redo restores) and one entry of the resolution selector.
// Dialogs and docks include only this header; no behaviour lives here.

#include "session/engine/network_impairment.h"
#include "spectral/vertex_ids.h"

#include <Eigen/Core>
#include <QByteArray>
#include <QString>

#include <cstdint>
#include <optional>

namespace sc::app {

/// Relaying a hosted session through NATS (issue 18; README "Viewers through NATS"): the host also publishes every
/// frame once to the broker, whatever the number of viewers (session::RelayPublisher).
struct HostRelaySettings {
  QString url;        ///< nats://HOST:PORT or tls://HOST:PORT (several: comma-separated)
  QString sessionId;  ///< session::isValidSessionId()
  QString user;
  QString password;  ///< kept by the relay publisher only (reconnections)
  QString caFile;    ///< TLS to the broker: the CA (PEM) to trust instead of the system's; empty: the system's
};

/// What HostController::host() needs. Validation of user input happens in the dialog; host() fails with failed()
/// on what only the attempt can reveal (unreadable mesh, port in use).
struct HostSettings {
  QString meshPath;                 ///< OFF, OBJ, PLY or STL, or a saved session (.shapecast)
  quint16 port = 47100;             ///< TCP port; 0 = any free port (see SessionController::tcpPort())
  std::optional<QString> password;  ///< none: open session
  int m = 100;                      ///< number of frequencies, 1 ≤ m < #V (clamped to #V − 1)
  QString name = QStringLiteral("host");
  bool useBasisCache = true;  ///< look up / store the basis in model::basisCacheDirectory()
  /// People who may hold a lock and drag their own handle at once (session::HostEngineOptions::maxEditors).
  int editors = 4;
  /// Also relay through NATS (issue 18 item 3); none: UDP peers only.
  std::optional<HostRelaySettings> relay;
};

/// What ClientController::join() needs.
struct JoinSettings {
  QString host = QStringLiteral("127.0.0.1");
  quint16 port = 47100;
  std::optional<QString> password;
  QString name;
  std::uint32_t level = 0;  ///< wanted display vertices; 0 = full resolution
  /// Overrides `level`: this fraction of the host's vertex count (e.g. 0.2 for "20 %"); ≥ 1 = full resolution.
  std::optional<double> levelFraction;
  /// Emulated network conditions on receive from the start (see SessionController::setNetworkConditions).
  std::optional<session::ImpairmentSettings> impairment;
  /// Pinned SHA-256 of the host's certificate (session::parseFingerprint); empty: trust on first use, as
  /// `shapecast-cli join` (the first fingerprint seen for host:port is remembered, a changed one is refused).
  QByteArray fingerprint;
  /// The known-hosts store (session::KnownHosts); empty: the application's QSettings (tests give an INI file).
  QString knownHostsFile;
};

/// How the host's certificate was trusted when joining (SessionController::hostTrust()).
enum class HostTrust {
  None,      ///< not joined (or hosting), or refused
  Pinned,    ///< matched the fingerprint the user entered
  Known,     ///< matched the fingerprint remembered from an earlier join of this host:port
  FirstUse,  ///< first join of this host:port: remembered now; the user should compare it with the host's once
};

/// Emulated network conditions of a client, as the Network conditions dock edits them.
struct NetworkConditions {
  double loss = 0.0;         ///< stationary loss probability, 0..1
  double burstLength = 1.0;  ///< mean burst of consecutive losses in datagrams; 1 = independent (Bernoulli) loss
  int delayMs = 0;           ///< fixed one-way delay added on receive
  double rateMbit = 0.0;     ///< link rate in Mbit/s for everything received (datagrams and stream); 0 = unlimited
};

/// The constraint set a user last sent (full-resolution ids, sorted and unique; anchors exclude the handle). The
/// shape is not in it: it is the session's coefficients, the sum of the edit steps (session/engine/edit_history.h).
struct HostConstraints {
  spectral::FullVertexIds handle;
  spectral::FullVertexIds anchors;

  friend bool operator==(const HostConstraints&, const HostConstraints&) = default;
};

/// One entry of the resolution selector.
struct LevelChoice {
  std::uint32_t target = 0;  ///< what setLevel() takes (0 = full resolution)
  QString label;             ///< "Full — N vertices", then "N vertices" (exact) or "≈ N vertices"
  bool current = false;      ///< the displayed level (exact list) or the target last asked for
};

}  // namespace sc::app
