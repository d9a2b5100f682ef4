#include "app/gui/port_reservation.h"

#include <QCoreApplication>
#include <QHostAddress>
#include <QTcpServer>

namespace sc::app {

PortReservation::PortReservation() = default;
PortReservation::~PortReservation() = default;
PortReservation::PortReservation(PortReservation&&) noexcept = default;
PortReservation& PortReservation::operator=(PortReservation&&) noexcept = default;

std::optional<PortReservation> PortReservation::take(quint16 port, QString* error) {
  PortReservation reservation;
  if (port == 0) return reservation;
  auto server = std::make_unique<QTcpServer>();
  if (!server->listen(QHostAddress::Any, port)) {
    if (error != nullptr) *error = portInUseText(port, server->errorString());
    return std::nullopt;
  }
  server->pauseAccepting();  // nobody is accepted before the session host listens
  reservation.m_server = std::move(server);
  return reservation;
}

bool PortReservation::holds() const { return m_server != nullptr && m_server->isListening(); }

quint16 PortReservation::port() const { return holds() ? m_server->serverPort() : 0; }

void PortReservation::release() {
  if (m_server != nullptr) m_server->close();
  m_server.reset();
}

QString portInUseText(quint16 port, const QString& reason) {
  return QCoreApplication::translate("HostController",
                                     "TCP port %1 is in use (%2). Choose another port, or 0 for any free port.")
      .arg(port)
      .arg(reason);
}

}  // namespace sc::app
