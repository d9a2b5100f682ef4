#pragma once
// Plain TCP connections that never start TLS nor send a byte (a stranger holding slots), for the security suites.

#include <QtNetwork/QHostAddress>
#include <QtNetwork/QTcpSocket>

#include <algorithm>
#include <memory>
#include <vector>

namespace sc::session::testing {

/// Opens `count` TCP connections from `source` to 127.0.0.1:`port` (connected by the event loop).
inline std::vector<std::unique_ptr<QTcpSocket>> openSilentConnections(const QHostAddress& source, quint16 port,
                                                                      int count) {
  std::vector<std::unique_ptr<QTcpSocket>> sockets;
  for (int i = 0; i < count; ++i) {
    auto socket = std::make_unique<QTcpSocket>();
    socket->bind(source);
    socket->connectToHost(QHostAddress::LocalHost, port);
    sockets.push_back(std::move(socket));
  }
  return sockets;
}

/// How many of `sockets` are connected (or connecting).
inline int stillOpen(const std::vector<std::unique_ptr<QTcpSocket>>& sockets) {
  return static_cast<int>(std::count_if(sockets.begin(), sockets.end(),
                                        [](const auto& s) { return s->state() != QAbstractSocket::UnconnectedState; }));
}

}  // namespace sc::session::testing
