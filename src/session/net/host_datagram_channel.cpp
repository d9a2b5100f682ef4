#include "session/net/host_datagram_channel.h"

#include "session/engine/session_clock.h"

#include <QtCore/QRandomGenerator>
#include <QtCore/QVariant>
#include <QtNetwork/QNetworkDatagram>
#include <QtNetwork/QUdpSocket>

#include <cassert>
#include <optional>
#include <utility>

namespace sc::session {

struct HostDatagramChannel::Peer {
  Peer(QByteArray datagramKey, QByteArray pathToken, std::uint16_t id, CodecOptions codec)
      : mac(datagramKey), token(std::move(pathToken)), encoder(std::move(datagramKey), id, codec) {}

  /// An address that sent an accepted PathOpen but has not yet echoed `challenge` (wire_format.h).
  struct Candidate {
    QHostAddress address;
    quint16 port = 0;
    std::uint64_t challenge = 0;
    std::uint64_t bytesReceived = 0;  ///< of accepted PathOpens from it
    std::uint64_t bytesSent = 0;      ///< challenges sent to it; kept ≤ bytesReceived
  };

  DatagramMac mac;  ///< PathOpen and probe tags, keyed once
  QByteArray token;
  CoefficientEncoder encoder;
  bool open = false;
  std::uint32_t highestSequence = 0;  ///< of the accepted PathOpens; 0 = none yet
  std::optional<Candidate> candidate;
  QHostAddress address;
  quint16 port = 0;
  std::uint64_t datagramsSent = 0;
  std::uint64_t bytesSent = 0;
  RateMeter payloadOut;
  RateMeter wireOut;
};

HostDatagramChannel::HostDatagramChannel(CodecOptions codec, QObject* parent)
    : QObject(parent), m_codec(codec), m_socket(new QUdpSocket(this)) {
  connect(m_socket, &QUdpSocket::readyRead, this, &HostDatagramChannel::readPending);
}

HostDatagramChannel::~HostDatagramChannel() = default;

bool HostDatagramChannel::bind(const QHostAddress& address, quint16 port, QString* error) {
  if (m_socket->state() != QAbstractSocket::UnconnectedState) m_socket->close();
  if (!m_socket->bind(address, port)) {
    if (error != nullptr) *error = m_socket->errorString();
    return false;
  }
  // Frames go out in bursts (P datagrams per peer per frame): a larger send buffer avoids local drops.
  m_socket->setSocketOption(QAbstractSocket::SendBufferSizeSocketOption, QVariant(1 << 20));
  return true;
}

quint16 HostDatagramChannel::port() const { return m_socket->localPort(); }

void HostDatagramChannel::addPeer(PeerId peer, QByteArray key, QByteArray token) {
  assert(peer >= 1 && peer <= 0xffff && "peer ids are 1..65535 (16-bit datagram field)");
  assert(!key.isEmpty() && "the datagram key must not be empty");
  if (peer < 1 || peer > 0xffff || key.isEmpty()) return;
  m_peers[peer] = std::make_unique<Peer>(std::move(key), std::move(token), static_cast<std::uint16_t>(peer), m_codec);
}

void HostDatagramChannel::removePeer(PeerId peer) { m_peers.erase(peer); }

bool HostDatagramChannel::pathOpen(PeerId peer) const {
  const auto it = m_peers.find(peer);
  return it != m_peers.end() && it->second->open;
}

QHostAddress HostDatagramChannel::peerAddress(PeerId peer) const {
  const auto it = m_peers.find(peer);
  return it != m_peers.end() && it->second->open ? it->second->address : QHostAddress();
}

quint16 HostDatagramChannel::peerPort(PeerId peer) const {
  const auto it = m_peers.find(peer);
  return it != m_peers.end() && it->second->open ? it->second->port : quint16{0};
}

void HostDatagramChannel::sendFrame(std::uint32_t frame, const Eigen::MatrixXd& Z, Micros inputArrivedAt) {
  assert(Z.rows() >= 1 && Z.rows() <= kMaxRows && Z.cols() == 3 && "Z must be m by 3, 1 <= m <= kMaxRows");
  if (Z.rows() < 1 || Z.rows() > kMaxRows || Z.cols() != 3) return;
  const std::uint32_t timestamp = wireTimestamp(inputArrivedAt);
  for (auto& [id, peer] : m_peers) {
    if (!peer->open) continue;
    const std::vector<QByteArray> datagrams = peer->encoder.encodeFrame(frame, Z, timestamp);
    const Micros now = sessionNow();
    for (const QByteArray& datagram : datagrams) {
      if (m_socket->writeDatagram(datagram, peer->address, peer->port) != datagram.size()) {
        ++m_sendErrors;
        continue;
      }
      const auto size = static_cast<std::uint64_t>(datagram.size());
      ++peer->datagramsSent;
      peer->bytesSent += size;
      peer->payloadOut.add(now, size);
      peer->wireOut.add(now, size + kUdpIpv4Overhead);
    }
  }
}

HostDatagramChannel::PeerTraffic HostDatagramChannel::traffic(PeerId peer) const {
  PeerTraffic traffic;
  const auto it = m_peers.find(peer);
  if (it == m_peers.end()) return traffic;
  const Micros now = sessionNow();
  traffic.datagramsSent = it->second->datagramsSent;
  traffic.bytesSent = it->second->bytesSent;
  traffic.payloadKbpsOut = it->second->payloadOut.kilobitsPerSecond(now);
  traffic.wireKbpsOut = it->second->wireOut.kilobitsPerSecond(now);
  return traffic;
}

std::uint64_t HostDatagramChannel::drops(PathOpenError reason) const {
  const auto index = static_cast<std::size_t>(reason);
  return index < m_drops.size() ? m_drops[index] : 0;
}

void HostDatagramChannel::readPending() {
  const auto lookup = [this](PeerId id) -> std::optional<PathCredentials> {
    const auto it = m_peers.find(id);
    if (it == m_peers.end()) return std::nullopt;
    return PathCredentials{&it->second->mac, it->second->token, it->second->highestSequence};
  };
  for (int read = 0; read < kMaxDatagramsPerPass && m_socket->hasPendingDatagrams(); ++read) {
    const QNetworkDatagram datagram = m_socket->receiveDatagram(kMaxDatagramSize);
    if (!datagram.isValid()) break;  // a socket error (e.g. a pending ICMP report): nothing to read
    const QByteArray bytes = datagram.data();
    const QHostAddress address = datagram.senderAddress();
    const auto port = static_cast<quint16>(datagram.senderPort());
    if (looksLikePathProbe(bytes, MessageType::PathResponse)) {
      onPathResponse(bytes, address, port);
      continue;
    }
    const PathOpenResult result = decodePathOpen(bytes, lookup);
    ++m_drops[static_cast<std::size_t>(result.error)];
    if (result.error != PathOpenError::None) continue;
    const auto it = m_peers.find(result.peer);
    if (it == m_peers.end()) continue;              // cannot happen: lookup found it
    it->second->highestSequence = result.sequence;  // accepted: strictly above the previous highest
    onPathOpen(result.peer, address, port);
  }
  // More pending: the rest is read in a later pass. The socket notifier is level-triggered, so readyRead fires
  // again on the next pass, after the events that queued up meanwhile. Not a queued call of readPending(): reading
  // outside readyRead can leave QAbstractSocket's unbuffered read notifier disabled with data pending (measured:
  // the client then stalled with 400 datagrams unread).
}

void HostDatagramChannel::onPathOpen(PeerId id, const QHostAddress& address, quint16 port) {
  Peer& peer = *m_peers.at(id);
  if (peer.open && peer.address == address && peer.port == port) return;  // the validated path, refreshed
  if (!peer.candidate || peer.candidate->address != address || peer.candidate->port != port) {
    peer.candidate = Peer::Candidate{address, port, QRandomGenerator::system()->generate64()};
  }
  Peer::Candidate& candidate = *peer.candidate;
  candidate.bytesReceived += kPathOpenSize;
  if (candidate.bytesSent + kPathProbeSize > candidate.bytesReceived) return;  // no amplification
  const QByteArray challenge =
      encodePathProbe(MessageType::PathChallenge, static_cast<std::uint16_t>(id), candidate.challenge, peer.mac);
  if (m_socket->writeDatagram(challenge, address, port) == challenge.size()) {
    candidate.bytesSent += static_cast<std::uint64_t>(challenge.size());
  } else {
    ++m_sendErrors;
  }
}

void HostDatagramChannel::onPathResponse(const QByteArray& bytes, const QHostAddress& address, quint16 port) {
  const auto it = m_peers.find(pathProbePeer(bytes));
  if (it == m_peers.end()) {
    ++m_drops[static_cast<std::size_t>(PathOpenError::Stranger)];
    return;
  }
  Peer& peer = *it->second;
  const PathProbeResult result = decodePathProbe(bytes, MessageType::PathResponse, peer.mac);
  PathOpenError error = result.error;
  if (error == PathOpenError::None) {
    const bool answers = peer.candidate && peer.candidate->address == address && peer.candidate->port == port &&
                         peer.candidate->challenge == result.challenge;
    if (!answers) error = PathOpenError::WrongChallenge;
  }
  if (error != PathOpenError::None) {
    ++m_drops[static_cast<std::size_t>(error)];
    return;
  }
  peer.open = true;
  peer.address = address;
  peer.port = port;
  peer.candidate.reset();
  emit pathOpened(it->first);
}

}  // namespace sc::session
