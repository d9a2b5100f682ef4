#pragma once
// Seeded network impairment for a receive path (issue 4 item 5): Bernoulli or Gilbert–Elliott loss, delay with
// uniform or normal jitter, reordering and duplication, so loss experiments run on loopback with real sockets and
// stay deterministic in CI. Pure: bytes and an injected clock in, bytes out at their delivery times; no sockets,
// no timers. The socket adapter calls push() for every datagram it reads and popDue() from a timer (nextDue()).
//
// Per offered datagram, in this order (one std::mt19937_64 stream, so a seed and the same push/popDue sequence
// give the same output on every platform's libstdc++/libc++ engine; the distributions are computed here, not by
// <random>'s implementation-defined distributions):
//   1. loss: Bernoulli(loss), or the Gilbert–Elliott chain below; a lost datagram is counted in dropped() only;
//   1b. rate (settings.rate.bitsPerSecond > 0, issue 17): the datagram passes the link's bottleneck (LinkRate,
//      link_rate.h): it leaves at its departure time, or is tail-dropped when the queue is full (counted in
//      dropped() and in rateDropped()); a lost datagram (step 1) uses no capacity. The LinkRate may be shared
//      with the client's stream reader (constructor), so that datagrams and the TLS stream share one rate;
//   2. delivery time = departure (the arrival without a rate) + delay + jitter sample, never earlier than the
//      departure;
//      jitter: Uniform in [−jitter, +jitter], or Normal(0, jitter) truncated to ±3·jitter;
//      jitter alone can reorder datagrams that arrive closer together than the jitter spread (as netem does);
//   3. reordering: with probability `reorder` the datagram is held back a further `reorderGap` (so datagrams
//      offered within reorderGap after it overtake it); counted in reordered();
//   4. duplication: with probability `duplicate` a second copy is queued with its own jitter sample; counted in
//      duplicated().
// Datagrams due at the same instant leave in offer order.
//
// Gilbert–Elliott parameterisation (pure Gilbert: every datagram in Bad is lost, none in Good; netem `gemodel p r`,
// see ../shared/design/protocol.md §5.1): with P(Good→Bad) = p and P(Bad→Good) = r per datagram,
//   mean burst (Bad sojourn) = 1/r,   stationary loss = P(Bad) = p/(p + r).
// From the settings (loss = ℓ, burstLength = L ≥ 1):   r = 1/L,   p = r·ℓ/(1 − ℓ).
// p ≤ 1 needs ℓ/(1 − ℓ) ≤ L (e.g. L = 1 allows ℓ ≤ 0.5); beyond that p is clamped to 1 and the realised loss is
// L/(L + 1) (goodToBad()/badToGood() return what is used). The chain starts in Good. Bernoulli loss is the special
// case r = 1 − ℓ, p = ℓ (mean burst 1/(1 − ℓ)), which is why a burst setting L > 1/(1 − ℓ) gives longer bursts.
//
// Settings outside their ranges are clamped (probabilities to [0, 1], times and burstLength to ≥ 0 / ≥ 1);
// loss ≥ 1 drops everything. Memory: O(datagrams in flight). Cost: O(log n) per push and per released datagram.

#include "session/engine/link_rate.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <chrono>
#include <cstdint>
#include <memory>
#include <queue>
#include <random>
#include <vector>

namespace sc::session {

using Millis = std::chrono::milliseconds;  ///< injected monotonic clock reading (same alias as lock_messages.h)

/// Shape of the jitter added to the fixed delay.
enum class JitterShape {
  Uniform,  ///< uniform in [−jitter, +jitter]
  Normal,   ///< normal with σ = jitter, truncated to ±3σ
};

struct ImpairmentSettings {
  double loss = 0.0;         ///< stationary loss probability in [0, 1]
  bool burst = false;        ///< false: Bernoulli loss; true: Gilbert–Elliott with mean burst `burstLength`
  double burstLength = 1.0;  ///< mean number of consecutive losses (datagrams), ≥ 1; only with `burst`
  Millis delay{0};           ///< fixed one-way delay added to every datagram
  Millis jitter{0};          ///< jitter spread (half-width for Uniform, σ for Normal)
  JitterShape jitterShape = JitterShape::Uniform;
  double reorder = 0.0;     ///< probability that a datagram is held back by `reorderGap`
  Millis reorderGap{10};    ///< extra hold of a reordered datagram
  double duplicate = 0.0;   ///< probability that a datagram is delivered twice
  LinkRateSettings rate{};  ///< bandwidth of the link (bitsPerSecond 0: unlimited)
  std::uint64_t seed = 1;   ///< seed of the std::mt19937_64 stream

  /// True when nothing is emulated (no loss, delay, jitter, reordering, duplication or rate).
  bool isIdeal() const {
    return loss <= 0.0 && delay.count() <= 0 && jitter.count() <= 0 && reorder <= 0.0 && duplicate <= 0.0 &&
           !(rate.bitsPerSecond > 0.0);
  }
};

/// Not thread-safe; one per receive path.
class NetworkImpairment {
 public:
  /// `link`: the bottleneck to use (shared with the stream reader); null: one is made from settings.rate when its
  /// rate is > 0, else the link has no rate.
  explicit NetworkImpairment(const ImpairmentSettings& settings = {}, std::shared_ptr<LinkRate> link = nullptr);

  /// Offers one datagram that arrived at `now`. Cost: O(log in-flight).
  void push(QByteArrayView bytes, Millis now);

  /// Every queued datagram whose delivery time is ≤ now, ordered by (delivery time, offer order). `now` should not
  /// go backwards (an earlier `now` simply releases less). Cost: O(k log in-flight) for k released.
  std::vector<QByteArray> popDue(Millis now);

  /// Delivery time of the next queued datagram, or Millis::max() when none (for the adapter's timer).
  Millis nextDue() const;
  std::size_t inFlight() const { return m_queue.size(); }

  std::uint64_t offered() const { return m_offered; }
  std::uint64_t dropped() const { return m_dropped; }
  std::uint64_t duplicated() const { return m_duplicated; }
  std::uint64_t reordered() const { return m_reordered; }
  /// Datagrams tail-dropped by the rate's queue (also counted in dropped()).
  std::uint64_t rateDropped() const { return m_rateDropped; }
  /// The bottleneck (nullptr without a rate).
  const std::shared_ptr<LinkRate>& link() const { return m_link; }
  std::uint64_t delivered() const { return m_delivered; }

  /// Transition probabilities in use: Gilbert–Elliott p and r as derived above; Bernoulli: p = ℓ, r = 1 − ℓ.
  double goodToBad() const { return m_goodToBad; }
  double badToGood() const { return m_badToGood; }
  const ImpairmentSettings& settings() const { return m_settings; }

 private:
  struct Pending {
    Millis due;
    std::uint64_t order;  ///< tie-break: offer order (copies after their original)
    QByteArray bytes;
  };
  struct Later {
    bool operator()(const Pending& a, const Pending& b) const {
      return a.due != b.due ? a.due > b.due : a.order > b.order;
    }
  };

  double uniform01();  ///< in [0, 1), 53 random bits
  bool bernoulli(double probability);
  bool lose();            ///< advances the loss model one datagram
  Millis jitterSample();  ///< signed, whole milliseconds

  ImpairmentSettings m_settings;
  std::mt19937_64 m_rng;
  double m_goodToBad = 0.0;
  double m_badToGood = 1.0;
  bool m_bad = false;
  std::priority_queue<Pending, std::vector<Pending>, Later> m_queue;
  std::uint64_t m_order = 0;
  std::uint64_t m_offered = 0;
  std::uint64_t m_dropped = 0;
  std::uint64_t m_duplicated = 0;
  std::uint64_t m_reordered = 0;
  std::uint64_t m_delivered = 0;
  std::uint64_t m_rateDropped = 0;
  std::shared_ptr<LinkRate> m_link;
};

}  // namespace sc::session
