#pragma once
// A viewer's rules for the relay (issue 18; docs/protocol.md, "Relay through NATS"): pure, clock injected, no
// sockets. The adapter (net/relay_viewer.h) feeds it the session facts, the keyframe and the frame messages in the
// order they arrived; it verifies each message against the pinned certificate, keeps the newest frame's Z (latest
// wins: an older or repeated frame is dropped as stale) and counts what it dropped and what it never saw.
//
// Late join: frames that arrive before the keyframe are buffered (at most kRelayJoinBuffer; the oldest go first);
// the keyframe sets Z, then the buffered frames newer than it are applied. Loss counts frame numbers skipped between
// two frames received live (the frames between the keyframe and the first live frame were published before the
// viewer subscribed); latency is sampled on live frames only (a keyframe's stamp is as old as the keyframe).
// Hostile input (malformed, bad signature, wrong row count) is dropped and counted, never asserted on.

#include "session/engine/recent_window.h"
#include "session/engine/relay_verified_messages.h"
#include "session/wire/relay_message.h"

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

namespace sc::session {

inline constexpr int kRelayJoinBuffer = 64;  ///< frames held while waiting for the keyframe

/// Why the facts were refused (None = accepted).
enum class RelayFactsStatus { None, Malformed, WrongFingerprint, BadSignature };

/// What a viewer counted. Latency is the host stamp's age at receipt (meaningful on one machine only).
struct RelayViewerStats {
  std::int64_t applied = 0;       ///< frames applied (the keyframe included)
  std::int64_t lost = 0;          ///< frame numbers skipped between applied frames
  std::int64_t stale = 0;         ///< authentic but not newer than the current frame (duplicate, late)
  std::int64_t malformed = 0;     ///< unreadable, or another row count than the facts say
  std::int64_t badSignature = 0;  ///< not signed by the pinned host
  std::int64_t overflowed = 0;    ///< dropped from the join buffer before the keyframe came
  double latencyP50Ms = 0;        ///< over the last 10 s
  double latencyP99Ms = 0;
};

class RelayReceiver {
 public:
  /// @param[in] sessionId  the session's id (bound into every signature).
  /// @param[in] pin  the host certificate's SHA-256 fingerprint; nullopt: trust the first facts (shown to the user).
  RelayReceiver(QString sessionId, std::optional<QByteArray> pin);

  /// The `session` facts message. Checks the certificate against the pin, then the signature with its key.
  /// Facts may come again (after a reconnection): the same certificate is accepted, another refused.
  RelayFactsStatus onFacts(QByteArrayView message);
  /// The `keyframe` value: applied like a frame, then the buffered frames newer than it. False when refused
  /// (counted) or when no facts were accepted yet.
  bool onKeyframe(QByteArrayView message, Micros now);
  /// A frame message from the frame subject: buffered until the keyframe, then applied when newer. True when it
  /// changed Z. Cost: one signature verify (≈ 55 µs) plus O(m).
  bool onFrame(QByteArrayView message, Micros now);
  /// An exact reference for distortion (the `keyframe` value read again, relay_display.h): verified and decoded
  /// like a frame but not applied. nullopt (counted as malformed or bad signature) when refused or before the facts.
  std::optional<RelayFrame> onReference(QByteArrayView message);
  /// Shares `verified` with the other receivers of this thread (relay_verified_messages.h): a frame message another
  /// of them verified is not verified again. Used only while it applies to this receiver's session and pin.
  void shareVerification(std::shared_ptr<RelayVerifiedMessages> verified) { m_shared = std::move(verified); }
  /// No keyframe exists (a host that published none yet): start from the buffered frames.
  void startWithoutKeyframe(Micros now);

  [[nodiscard]] bool hasFacts() const { return m_verifier != nullptr; }
  [[nodiscard]] const RelayFacts& facts() const { return m_facts; }
  [[nodiscard]] QByteArray fingerprint() const { return relayCertificateFingerprint(m_facts.certificateDer); }
  /// True once a keyframe (or startWithoutKeyframe) ended the join.
  [[nodiscard]] bool joined() const { return m_joined; }
  /// The newest frame number applied; nullopt before the first.
  [[nodiscard]] std::optional<std::uint32_t> frame() const { return m_frame; }
  /// The newest Z applied (m by 3; empty before the first).
  [[nodiscard]] const Eigen::MatrixXd& coefficients() const { return m_Z; }
  [[nodiscard]] RelayViewerStats stats(Micros now) const;

 private:
  /// Verifies and decodes one frame message; nullopt (counted) when refused.
  std::optional<RelayFrame> authentic(QByteArrayView message);
  /// `live`: from the frame subject (not the keyframe): latency is sampled, and from the first one on skipped frame
  /// numbers count as lost.
  bool apply(RelayFrame frame, Micros now, bool live);

  QString m_sessionId;
  std::optional<QByteArray> m_pin;
  RelayFacts m_facts;
  std::unique_ptr<RelayVerifier> m_verifier;
  std::deque<QByteArray> m_buffer;  ///< frames before the keyframe, oldest first
  bool m_joined = false;
  bool m_liveSeen = false;
  std::optional<std::uint32_t> m_frame;
  Eigen::MatrixXd m_Z;
  RelayViewerStats m_counts;
  RecentSamples m_latency;
  std::shared_ptr<RelayVerifiedMessages> m_shared;  ///< null: every message verified here
};

}  // namespace sc::session
