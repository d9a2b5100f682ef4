#pragma once
// The host's view of its relay viewers (issue 18): the latest Stats message of each viewer (relay_message.h, kind 3)
// folded into one aggregate (count, loss, latency and distortion distributions), not one row per viewer. Pure, clock
// injected. Input is untrusted (any holder of the viewer credential may send): malformed messages are dropped and
// counted, at most kMaxTrackedViewers are kept (the stalest is evicted), and a viewer silent for kRelayViewerTimeout is
// forgotten.

#include "session/engine/recent_window.h"
#include "session/wire/relay_message.h"

#include <QtCore/QByteArrayView>

#include <cstdint>
#include <unordered_map>

namespace sc::session {

inline constexpr int kMaxTrackedViewers = 10000;
inline constexpr Micros kRelayViewerTimeout{10'000'000};

/// Distribution of one figure across viewers: nearest-rank percentiles.
struct Spread {
  double min = 0;
  double median = 0;
  double p90 = 0;
  double max = 0;
};

struct RelayAudienceSummary {
  int viewers = 0;                ///< reported within kRelayViewerTimeout
  Spread lossFraction;            ///< lost / (applied + lost) since each viewer started
  Spread latencyP99Ms;            ///< each viewer's own p99 over its last 10 s
  std::int64_t badSignature = 0;  ///< summed over the viewers: forged frames they dropped
  int distortionViewers = 0;      ///< viewers that measured distortion (they fetched a level)
  Spread distortionMeanPct;       ///< their mean distortion, % of the rest bounding-box diagonal
  Spread distortionMaxPct;        ///< their largest
  std::int64_t concealed = 0;     ///< summed over the viewers: frames predicted
  std::int64_t malformed = 0;     ///< Stats messages this host dropped
};

class RelayAudience {
 public:
  /// One Stats message as received. False (counted) when malformed.
  bool onStats(QByteArrayView message, Micros now);
  [[nodiscard]] RelayAudienceSummary summary(Micros now) const;

 private:
  struct Entry {
    RelayStats stats;
    Micros at{0};
  };
  void forgetSilent(Micros now);

  std::unordered_map<std::uint64_t, Entry> m_viewers;
  std::int64_t m_malformed = 0;
};

}  // namespace sc::session
