#pragma once
// A malicious session host for the client's tests (docs/security.md, "Hostile host"): a TLS 1.3 server on
// 127.0.0.1 (the suite's own self-signed identity) that accepts one client and speaks the protocol only as the
// test scripts it: it sends whatever messages, sizes and datagrams the test asks for (an oversized ModelBegin and a
// stream of chunks behind it, a 1-iteration Challenge, absurd levels, huge coefficients) and records what the
// client sends. The mirror of RawControlPeer (a hand-driven client against a real SessionHost).

#include "received_messages.h"
#include "session/net/tls_identity.h"
#include "session/net/tls_server.h"
#include "session/wire/control_frame.h"
#include "session/wire/control_messages.h"

#include <QtCore/QByteArray>
#include <QtNetwork/QHostAddress>
#include <QtNetwork/QSslSocket>
#include <QtNetwork/QUdpSocket>
#include <QtTest/QTest>

#include <memory>
#include <optional>
#include <vector>

namespace sc::session::testing {

inline constexpr int kHostileWaitMs = 3000;  ///< upper bound for one awaited condition

class HostileHost {
 public:
  /// Listens on 127.0.0.1 (any TCP port) with `identity`, and binds a UDP socket (any port) for datagrams.
  explicit HostileHost(const TlsIdentity& identity);
  HostileHost(const HostileHost&) = delete;
  HostileHost& operator=(const HostileHost&) = delete;
  ~HostileHost();

  [[nodiscard]] quint16 port() const { return m_server.serverPort(); }
  [[nodiscard]] quint16 udpPort() const { return m_udp.localPort(); }
  /// Waits (event loop running) for the client's Hello; false after kHostileWaitMs.
  bool awaitHello();
  /// Encodes and writes one message (nothing before a client connected).
  void send(const ControlMessage& message);
  /// Writes `count` ModelChunks of `chunkBytes` bytes of transfer `id` announced with `totalSize`, as the socket
  /// drains (never more than 1 MiB queued here, so that the host's own buffers stay small); stops when the client
  /// closes. Returns the chunks written.
  int streamChunks(std::uint32_t id, std::uint32_t totalSize, int count, int chunkBytes = kMaxChunkBytes);
  /// Waits for the client's first PathOpen datagram and sends `datagrams` to its source address.
  bool sendDatagrams(const std::vector<QByteArray>& datagrams);
  /// True once the client closed the connection (waits up to `timeoutMs`).
  bool clientClosed(int timeoutMs = kHostileWaitMs);

  /// Waits for the first received message of type T not yet taken, and takes it; nullopt after `timeoutMs`.
  template <typename T>
  std::optional<T> take(int timeoutMs = kHostileWaitMs) {
    return takeReceived<T>(m_received, timeoutMs);
  }

 private:
  void accept();
  void readAvailable();

  TlsServer m_server;
  QSslSocket* m_client = nullptr;  ///< owned by this object once accepted
  QUdpSocket m_udp;
  ControlFrameReader m_reader;
  std::vector<ControlMessage> m_received;
};

/// Resident memory of this process now, in bytes (/proc/self/statm): what a client under attack holds.
std::uint64_t residentBytes();

}  // namespace sc::session::testing
