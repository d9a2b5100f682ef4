#pragma once
// PortReservation: the TCP port a host will listen on, held from the moment hosting is asked for (issue 16). The
// basis of a large mesh takes seconds; a port that is busy must be an error before that work starts, naming the
// port, and nothing else may take the port meanwhile. A reservation is a QTcpServer listening on the port (on
// QHostAddress::Any, as SessionHost does) that accepts nobody: a connection that arrives meanwhile waits in the
// backlog and is reset at release(). HostController releases it right before SessionHost::start() listens on the
// same port (one function call apart). The session's datagrams use a port of their own (any free one), so only
// the TCP port is reserved. Cost: one listen(), O(1).

#include <QString>

#include <memory>
#include <optional>

class QTcpServer;

namespace sc::app {

class PortReservation {
 public:
  PortReservation();  ///< holds nothing
  ~PortReservation();
  PortReservation(PortReservation&&) noexcept;
  PortReservation& operator=(PortReservation&&) noexcept;
  PortReservation(const PortReservation&) = delete;
  PortReservation& operator=(const PortReservation&) = delete;

  /// Listens on `port`. Port 0 (any free port) needs no reservation: an empty one. nullopt when the port is taken,
  /// with portInUseText() in *error.
  [[nodiscard]] static std::optional<PortReservation> take(quint16 port, QString* error = nullptr);

  /// Whether a port is held now.
  [[nodiscard]] bool holds() const;
  /// The port held (0 when none).
  [[nodiscard]] quint16 port() const;
  /// Stops listening (idempotent): the port is free for SessionHost::start().
  void release();

 private:
  std::unique_ptr<QTcpServer> m_server;
};

/// "TCP port P is in use (REASON). Choose another port, or 0 for any free port." — the readable error of a busy port.
[[nodiscard]] QString portInUseText(quint16 port, const QString& reason);

}  // namespace sc::app
