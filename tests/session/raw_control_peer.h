#pragma once
// A control connection to a SessionHost driven by hand, for tests that need what SessionClient never does: raw
// bytes, malformed or oversized frames, a peer that stops reading or stops talking, a connection that vanishes.
// Every decoded message from the host is kept in order. The transport (TLS 1.3 since docs/security.md) is chosen in one
// place, RawControlPeer's constructor (raw_control_peer.cpp), so that the fault tests follow the control channel when
// it moves to TLS.

#include "received_messages.h"
#include "session/wire/control_frame.h"
#include "session/wire/control_messages.h"

#include <QtCore/QByteArray>
#include <QtNetwork/QSslSocket>
#include <QtTest/QTest>

#include <memory>
#include <optional>
#include <vector>

namespace sc::session::testing {

inline constexpr int kRawWaitMs = 8000;  ///< upper bound for one awaited condition

class RawControlPeer {
 public:
  /// Connects to 127.0.0.1:`port` (see connected()). `receiveBufferBytes` > 0: the socket's SO_RCVBUF, set
  /// before connecting (it bounds the TCP window, so a peer that stops reading holds the host back at once).
  explicit RawControlPeer(quint16 port, int receiveBufferBytes = 0);
  ~RawControlPeer();
  RawControlPeer(const RawControlPeer&) = delete;
  RawControlPeer& operator=(const RawControlPeer&) = delete;

  /// Waits (event loop running) until connected and the TLS handshake is done; false after kRawWaitMs.
  bool connected();
  /// Encodes and writes one message.
  void send(const ControlMessage& message);
  /// Writes bytes as they are (a hand-built frame, garbage, a partial header).
  void sendRaw(const QByteArray& bytes);
  /// Waits until the host closed the connection; false after kRawWaitMs.
  bool closedByHost();
  /// Stops reading: what the host sends from now on piles up in the kernel's buffers (a client that hangs).
  void stopReading();
  /// Drops the connection at once, as the kernel does for a killed process (unread bytes: a TCP reset).
  void abort();

  /// Waits for the first received message of type T not yet taken, and takes it; nullopt after `timeoutMs`.
  template <typename T>
  std::optional<T> take(int timeoutMs = kRawWaitMs) {
    return takeReceived<T>(m_received, timeoutMs);
  }
  /// Hello (open session) → the Welcome; nullopt if none came.
  std::optional<Welcome> join(const QString& name);
  /// Requests the lock and waits for its grant to `self`; kNoEpoch if none came.
  LockEpoch acquireLock(PeerId self);

 private:
  void readAvailable();

  std::unique_ptr<QSslSocket> m_socket;
  ControlFrameReader m_reader;
  std::vector<ControlMessage> m_received;
  bool m_reading = true;
};

}  // namespace sc::session::testing
