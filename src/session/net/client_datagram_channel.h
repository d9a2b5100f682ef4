#pragma once
// The client's UDP side of a session: one QUdpSocket that keeps the host's path open (PathOpen datagrams,
// path_open.h) and receives the coefficient stream into a FrameAssembler, optionally through a seeded
// NetworkImpairment, feeding ReceiverStatistics. The thin socket/timer adapter over the pure engines
// (style.md item 11); the TCP SessionClient owns it and opens it after the Welcome.
//
// Receive path: readyRead → at most kMaxDatagramsPerPass pending datagrams (the rest in the next event-loop pass)
// → an authentic PathChallenge from the host is answered at once with a PathResponse (path_open.h), anything else
// → [NetworkImpairment::push(bytes, now); a precise single-shot
// timer at nextDue() releases them] → FrameAssembler::receive. Every datagram that passes authentication (also
// one then dropped as Late) is recorded in the statistics (sequence, unwrapped header timestamp, arrival, payload
// and payload + 28 bytes); one that changed Z emits frameUpdated(). With Concealment::Extrapolate a FramePredictor
// (frame_predictor.h) turns the assembler's Z into the displayed Z, and a precise single-shot timer at its
// nextDue() shows predicted frames while the next frame is overdue (frameUpdated(k + j)) and takes them back
// (predictionWithdrawn(k), then frameUpdated(k)). Datagrams are not filtered by source address:
// the per-client AEAD tag is the check. Drops are counted by reason in assembler(); nothing is asserted on input.
// Not thread-safe: use from the thread that owns it.

#include "session/engine/frame_assembler.h"
#include "session/engine/frame_predictor.h"
#include "session/engine/network_impairment.h"
#include "session/engine/receiver_statistics.h"
#include "session/wire/datagram_mac.h"
#include "session/wire/lock_messages.h"

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QObject>
#include <QtCore/QString>
#include <QtNetwork/QHostAddress>

#include <cstdint>
#include <memory>
#include <optional>

class QTimer;
class QUdpSocket;

namespace sc::session {

struct ClientDatagramOptions {
  Concealment concealment = Concealment::HoldLast;
  std::optional<ImpairmentSettings> impairment;  ///< set: simulate loss/delay/reorder/duplication on receive
  PredictorSettings predictor;                   ///< used with Concealment::Extrapolate only
  /// The link's bottleneck shared with the TLS stream reader (SessionClient); null: the impairment makes its own
  /// from impairment->rate when that has a rate.
  std::shared_ptr<LinkRate> link;
};

class ClientDatagramChannel : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ClientDatagramChannel)

 public:
  /// Interval of PathOpen datagrams until the first coefficient datagram is accepted (then kPathRefreshMs).
  static constexpr int kPathOpenIntervalMs = 500;
  /// Datagrams read per event-loop pass (Issue 14 item 11); readyRead fires again for the rest.
  static constexpr int kMaxDatagramsPerPass = 64;

  explicit ClientDatagramChannel(ClientDatagramOptions options = {}, QObject* parent = nullptr);
  ~ClientDatagramChannel() override;

  /// Binds the socket to `local` on any free port (see localPort()). @param[out] error  the socket's error text
  /// (may be null). Also asks for a 1 MiB receive buffer (frames arrive in bursts of P datagrams).
  bool bind(const QHostAddress& local, QString* error);
  quint16 localPort() const;

  /// Starts receiving frames for `self` and sends a PathOpen to host:udpPort at once, then every
  /// kPathOpenIntervalMs until the first accepted coefficient datagram, then every kPathRefreshMs. Each PathOpen
  /// carries the next sequence number, from 1 per open() (the host drops any not above the highest it accepted);
  /// rebinding the socket with bind() while open keeps the count, so the next PathOpen moves the host's path.
  /// @param[in] key, token  datagramKey and pathToken from the Welcome. @param[in] m  rows of Z, 1..kMaxRows.
  /// Opening again (e.g. a new session) starts a fresh assembler, statistics and impairment.
  void open(const QHostAddress& host, quint16 udpPort, PeerId self, QByteArray key, QByteArray token, int m);
  /// Stops sending PathOpens and ignores (reads and discards) datagrams from then on. Counters, Z and statistics
  /// stay readable.
  void close();
  bool isOpen() const { return m_open; }

  /// Exact Z of a join Keyframe (frame `frame`). Ignored once a coefficient datagram was applied, when Z is not
  /// m by 3, or when older than an earlier seed (FrameAssembler::seed). Before open() it is kept and applied
  /// by open() when m matches. Emits frameUpdated(frame) when applied.
  void seed(std::uint32_t frame, const Eigen::MatrixXd& Z);

  /// The displayed Z, m by 3 (zeros before any frame: the rest shape); 0 by 3 before open(). The assembler's
  /// concealed Z, or with Concealment::Extrapolate the predictor's display.
  const Eigen::MatrixXd& coefficients() const;
  /// Frame number coefficients() stands for: the assembler's current frame, or with Extrapolate a predicted one
  /// (receivedFrame() + predicted frames).
  std::uint32_t currentFrame() const;
  /// The newest frame number received (the assembler's current frame).
  std::uint32_t receivedFrame() const;
  /// True after a seed or an applied datagram.
  bool hasFrame() const;

  /// Receiver report (loss, jitter, kbit/s, fps, latency); report() starts a new loss interval.
  ReceiverReport report(Micros now);
  ReceiverReport peek(Micros now) const;
  /// Starts the latency percentiles over (ReceiverStatistics::clearLatency()); nothing before open().
  void clearLatency();

  /// Frames applied: +1 whenever an accepted datagram starts a new frame number (seeds are not counted).
  std::uint64_t framesApplied() const { return m_framesApplied; }
  /// Datagrams dropped by the assembler (every reason) plus those read while closed or before open(). Losses
  /// simulated by the impairment are not drops (they show as loss in report(); see impairment()->dropped()).
  std::uint64_t droppedDatagrams() const;
  /// Datagrams read from the socket (before the impairment), path challenges not included.
  std::uint64_t datagramsRead() const { return m_datagramsRead; }
  /// Payload bytes of those datagrams.
  std::uint64_t bytesRead() const { return m_bytesRead; }
  /// Authentic PathChallenges answered (each with one PathResponse).
  std::uint64_t pathChallengesAnswered() const { return m_pathChallengesAnswered; }
  /// PathOpen datagrams sent (over every open()).
  std::uint64_t pathOpensSent() const { return m_pathOpensSent; }
  /// Current PathOpen interval: kPathOpenIntervalMs until the first accepted datagram, then kPathRefreshMs;
  /// 0 when not open.
  int pathOpenIntervalMs() const;

  /// Per-reason drop counters (nullptr before open()).
  const FrameAssembler* assembler() const { return m_assembler.get(); }
  /// The dead reckoning in use (nullptr unless Concealment::Extrapolate, or before open()).
  const FramePredictor* predictor() const { return m_predictor.get(); }
  /// The impairment in use (nullptr without one configured, or before open()).
  const NetworkImpairment* impairment() const { return m_impairment.get(); }

  /// Changes the simulated network conditions, also while open (a user moving a "loss" slider); nullopt removes
  /// the impairment. Datagrams read from then on go through the new settings. Datagrams the old impairment still
  /// holds back (its delay, jitter or reordering) are delivered at once, in their release order, before anything
  /// else: the old model already decided they survive, so dropping them would add loss neither setting asked for,
  /// and holding them on the old schedule would mix two models. The new impairment starts a fresh loss chain (in
  /// Good) from settings->seed. Receiver statistics, Z and counters carry on (loss intervals simply see the new
  /// rate). Before open() the settings are kept for open(); a later open() uses the latest settings.
  /// `link`: the bottleneck to share (see ClientDatagramOptions::link); it replaces the one given before.
  void setImpairment(std::optional<ImpairmentSettings> settings, std::shared_ptr<LinkRate> link = nullptr);
  /// The settings set at construction or by setImpairment() (nullopt: none).
  const std::optional<ImpairmentSettings>& impairmentSettings() const { return m_options.impairment; }

 signals:
  /// After each change of the displayed Z: an accepted datagram or applied seed, and with Extrapolate a predicted
  /// frame or a withdrawal; `frame` is currentFrame() (a predicted frame number included).
  void frameUpdated(std::uint32_t frame);
  /// Extrapolate only: the predicted frames after `frame` were taken back (no datagram came; the stream has most
  /// likely stopped); frameUpdated(frame) follows with the received frame's Z on display again.
  void predictionWithdrawn(std::uint32_t frame);

 private:
  std::unique_ptr<NetworkImpairment> makeImpairment() const;  ///< from m_options (nullptr without an impairment)
  void readPending();
  void releaseDue();
  void armReleaseTimer();
  void armPredictTimer();
  void predictDue();
  void process(const QByteArray& bytes, Micros now);
  void sendPathOpen();
  /// True when `bytes` was a PathChallenge (answered if authentic); false: a coefficient datagram to process.
  bool answerPathChallenge(const QByteArray& bytes);

  ClientDatagramOptions m_options;
  QUdpSocket* m_socket = nullptr;    ///< child of this
  QTimer* m_pathTimer = nullptr;     ///< PathOpen resend
  QTimer* m_releaseTimer = nullptr;  ///< impairment delivery (precise, single-shot)
  QTimer* m_predictTimer = nullptr;  ///< FramePredictor::nextDue() (precise, single-shot)
  bool m_open = false;
  QHostAddress m_host;
  quint16 m_hostPort = 0;
  std::uint16_t m_self = 0;            ///< peer id for the PathOpens
  QByteArray m_key;                    ///< datagram key (PathOpen tag)
  std::unique_ptr<DatagramMac> m_mac;  ///< keyed with m_key: path challenges and responses
  QByteArray m_token;                  ///< path token
  std::uint32_t m_pathSequence = 0;    ///< of the last PathOpen sent; 0 after open()
  std::unique_ptr<FrameAssembler> m_assembler;
  std::unique_ptr<FramePredictor> m_predictor;
  std::unique_ptr<NetworkImpairment> m_impairment;
  std::unique_ptr<ReceiverStatistics> m_statistics;
  std::optional<std::pair<std::uint32_t, Eigen::MatrixXd>> m_pendingSeed;
  Eigen::MatrixXd m_empty;  ///< 0 by 3, coefficients() before open()
  std::uint64_t m_framesApplied = 0;
  std::uint64_t m_unopenedDrops = 0;
  std::uint64_t m_datagramsRead = 0;
  std::uint64_t m_bytesRead = 0;
  std::uint64_t m_pathOpensSent = 0;
  std::uint64_t m_pathChallengesAnswered = 0;
};

}  // namespace sc::session
