#pragma once
// The set-up of datagram_channel_tests (the datagram_channel_*_test.cpp files): a HostDatagramChannel and a
// ClientDatagramChannel bound to 127.0.0.1 with one peer's key and path token, spectrum-like coefficients to send,
// a third socket that is neither, and waiting in the event loop. Needs the QCoreApplication of socket_test_main.cpp.

#include "session/net/client_datagram_channel.h"
#include "session/net/host_datagram_channel.h"
#include "session/wire/path_open.h"

#include <Eigen/Core>

#include <QtCore/QByteArray>
#include <QtNetwork/QHostAddress>
#include <QtNetwork/QUdpSocket>

#include <cstdint>
#include <functional>

namespace sc::session::testing {

inline constexpr PeerId kPeer = 7;  ///< the one peer of a Session
inline constexpr int kM = 100;      ///< coefficient rows of the frames sent
inline const QHostAddress kLoopback{QHostAddress::LocalHost};
/// `size` bytes of `fill` (keys and tokens, right or wrong).
inline QByteArray bytesOf(char fill, int size) { return QByteArray(size, fill); }
inline const QByteArray kKey = bytesOf('k', kDatagramKeySize);  ///< kPeer's datagram key
inline const QByteArray kToken = bytesOf('t', kPathTokenSize);  ///< kPeer's path token

/// Runs the event loop until `done` or `timeoutMs`; blocks in the event loop (no busy wait), waking at least
/// every 5 ms to re-check. True when `done` held.
bool waitUntil(const std::function<bool()>& done, int timeoutMs = 5000);

/// Spectrum-like coefficients (m × 3): uniform in ±1/(1 + row), from a generator seeded with `seed`.
Eigen::MatrixXd frameZ(unsigned seed, int m = kM);

/// A host and a client on loopback (binding failures are test failures), kPeer known to the host; open() opens the
/// client's path.
struct Session {
  explicit Session(ClientDatagramOptions options = {});
  /// Opens the client's path to the host (PathOpen) and waits until the host has it; false after the timeout.
  bool open();
  /// Sends `frames` frames starting at `first`, in batches small enough for the socket buffers, and waits until
  /// the client has read every datagram sent; false when a batch did not arrive in time.
  bool stream(std::uint32_t first, int frames, int batch = 25);

  HostDatagramChannel host;
  ClientDatagramChannel client;
};

/// A socket on loopback that is neither the host nor the client (a failed bind is a test failure).
struct Stranger {
  Stranger();
  /// Sends `bytes` to 127.0.0.1:`port`.
  void send(const QByteArray& bytes, quint16 port);
  /// Waits for a PathChallenge for kPeer (kKey) on this socket, reading and discarding anything else, and answers
  /// it with the PathResponse to 127.0.0.1:`port`: what a client at this address does. False after the timeout.
  bool answerChallenge(quint16 port);
  QUdpSocket socket;
};

}  // namespace sc::session::testing
