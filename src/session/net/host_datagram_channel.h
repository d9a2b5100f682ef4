#pragma once
// The host's UDP side of a session: one QUdpSocket that receives path-open datagrams from clients (path_open.h)
// and sends every frame's coefficient datagrams (coefficient_codec.h) to each client whose path is open. The thin
// socket adapter over the pure codecs (style.md item 11); the TCP SessionHost owns it and tells it who joined.
//
// Path rule (docs/protocol.md, "Datagram key and path"): a peer added with addPeer() receives nothing until a
// PathOpen with its peer id, key and token arrives; the datagram's source address and port become the peer's
// *candidate* path, and the host sends it a PathChallenge (a random u64, path_open.h). Only a PathResponse with
// that value from that address and port validates the path: from then on the peer's coefficient datagrams go
// there (first path, and later a move: NAT rebinding). Until then they keep going to the previous validated path,
// and the candidate gets nothing but challenges, at most as many bytes as the accepted PathOpens it sent (Issue 14
// item 6: a member can no longer point its stream at a victim). A PathOpen is valid only if its sequence is above
// the highest accepted from that peer since addPeer(), so a recorded one resent from elsewhere is dropped as
// Replayed. Invalid datagrams are dropped and counted per PathOpenError (style.md item 6), never answered.
// Receive loop: at most kMaxDatagramsPerPass datagrams per readyRead; the rest waits for the next event-loop pass
// (readyRead fires again), so a flood cannot hold the event loop (timers, TCP) for long.
// Not thread-safe: use from the thread that owns it (its socket's thread).

#include "session/engine/receiver_statistics.h"
#include "session/wire/coefficient_codec.h"
#include "session/wire/lock_messages.h"
#include "session/wire/path_open.h"

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QObject>
#include <QtCore/QString>
#include <QtNetwork/QHostAddress>

#include <array>
#include <cstdint>
#include <map>
#include <memory>

class QUdpSocket;

namespace sc::session {

/// IPv4 (20) + UDP (8) header bytes counted on the wire per datagram for the "wire" kbit/s figures.
inline constexpr int kUdpIpv4Overhead = 28;

class HostDatagramChannel : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(HostDatagramChannel)

 public:
  /// @param[in] codec  datagram layout of every peer's encoder (parts, protected rows, band size).
  /// Datagrams read per event-loop pass (item 11 of Issue 14): ≈ 64 × 1 µs of work before other events run.
  static constexpr int kMaxDatagramsPerPass = 64;

  explicit HostDatagramChannel(CodecOptions codec = {}, QObject* parent = nullptr);
  ~HostDatagramChannel() override;

  /// Binds the socket. @param[in] port  0 = any free port (see port()). @param[out] error  the socket's error text
  /// on failure (may be null). Returns false on failure; binding twice re-binds.
  bool bind(const QHostAddress& address, quint16 port, QString* error);
  /// The bound port; 0 when not bound.
  quint16 port() const;

  /// Registers a joined client: its peer id (1..65535, the datagram header holds 16 bits; others are ignored),
  /// datagram key (non-empty) and path token (kPathTokenSize bytes). Its path stays closed until a valid PathOpen.
  /// Re-adding a peer replaces its credentials, closes its path, restarts its encoder (sequence 0) and forgets the
  /// highest PathOpen sequence accepted from it (the client starts again at 1 after a new Welcome).
  void addPeer(PeerId peer, QByteArray key, QByteArray token);
  /// Forgets a peer (it left): nothing more is sent to it and its PathOpens count as Stranger.
  void removePeer(PeerId peer);
  /// True once a path of this (added) peer was validated (PathOpen, then the PathResponse to its challenge).
  bool pathOpen(PeerId peer) const;

  /// Encodes Z once per open path (each peer has its own key and sequence numbers) and sends the datagrams.
  /// @param[in] frame  global frame number (the caller increments it per frame).
  /// @param[in] Z  m by 3 coefficients, 1 ≤ m ≤ kMaxRows.
  /// @param[in] inputArrivedAt  session clock when the input that produced the frame arrived; written into the
  ///            header as wireTimestamp(inputArrivedAt) (receivers derive jitter and, on one machine, latency).
  /// Cost per open path: CoefficientEncoder::encodeFrame (O(m) + P AES-GCM seals) plus P sendto() calls. A failed send
  /// (e.g. a full socket buffer) is counted in sendErrors() and otherwise ignored: datagrams are not retried.
  void sendFrame(std::uint32_t frame, const Eigen::MatrixXd& Z, Micros inputArrivedAt);

  struct PeerTraffic {
    std::uint64_t datagramsSent = 0, bytesSent = 0;  ///< UDP payload bytes since addPeer()
    double payloadKbpsOut = 0, wireKbpsOut = 0;      ///< over the last second
  };
  /// What was sent to one peer; zeros for an unknown peer. Rates: kbit/s over the last second (RateMeter) at
  /// sessionNow(); wire = payload + kUdpIpv4Overhead per datagram. Cost: O(datagrams in the last second).
  PeerTraffic traffic(PeerId peer) const;

  /// PathOpen and PathResponse datagrams dropped for `reason` (None: the count of accepted PathOpens).
  std::uint64_t drops(PathOpenError reason) const;
  /// Datagrams the socket refused to send.
  std::uint64_t sendErrors() const { return m_sendErrors; }
  /// The UDP address (and port) a peer's path points to; null address when closed or unknown.
  QHostAddress peerAddress(PeerId peer) const;
  quint16 peerPort(PeerId peer) const;

 signals:
  /// A peer's first path was validated, and again whenever another address or port was validated.
  void pathOpened(PeerId peer);

 private:
  struct Peer;
  void readPending();
  void onPathOpen(PeerId id, const QHostAddress& address, quint16 port);
  void onPathResponse(const QByteArray& bytes, const QHostAddress& address, quint16 port);

  CodecOptions m_codec;
  QUdpSocket* m_socket = nullptr;  ///< child of this
  std::map<PeerId, std::unique_ptr<Peer>> m_peers;
  std::array<std::uint64_t, static_cast<std::size_t>(PathOpenError::Count)> m_drops{};
  std::uint64_t m_sendErrors = 0;
};

}  // namespace sc::session
