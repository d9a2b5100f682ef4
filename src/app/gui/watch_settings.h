#pragma once
// What `shapecast --watch` needs to watch a relayed session through NATS (issue 18 item 2; README "Watching through
// NATS"): the broker, the viewer credential, the session id, the pinned host certificate and the wanted level. The
// viewer never connects to the host: frames, the keyframe, the level list and the level payloads come from the
// broker, signed with the host's TLS identity key.

#include "session/engine/frame_assembler.h"

#include <QByteArray>
#include <QString>

#include <cstdint>
#include <optional>

namespace sc::app {

struct WatchSettings {
  QString url;        ///< nats://HOST:PORT or tls://HOST:PORT (comma-separated for several)
  QString sessionId;  ///< session::isValidSessionId()
  QString user;       ///< the viewer credential
  QString password;
  QString caFile;           ///< TLS to the broker: the CA (PEM) to trust instead of the system's (--nats-ca)
  QByteArray pin;           ///< the host certificate's SHA-256; empty: trust the first facts (shown in the window)
  std::uint32_t level = 0;  ///< wanted display vertices; 0 = full resolution
  std::optional<double> levelFraction;  ///< overrides `level`: this fraction of the host's vertex count
  /// What a missed frame shows (the app has no concealment setting: hold-last; Extrapolate predicts overdue frames).
  session::Concealment concealment = session::Concealment::HoldLast;
};

/// Empty when `settings` can be used to watch; otherwise the readable reason (a bad URL: app/common/nats_url.h, a bad
/// session id, an unreadable CA file).
QString validateWatchSettings(const WatchSettings& settings);

}  // namespace sc::app
