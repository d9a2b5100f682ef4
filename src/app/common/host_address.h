#pragma once
// "HOST:PORT" as a user types it, for `shapecast --join` and the `shapecast-cli join|drive` commands alike.

#include <QString>
#include <QtGlobal>

#include <optional>

namespace sc::app {

/// A host and TCP port, as typed (the host is not resolved).
struct HostAddress {
  QString host;      ///< a name, an IPv4 address or an IPv6 address (without brackets)
  quint16 port = 0;  ///< 1..65535
};

/// Parses "HOST:PORT". HOST is a name or an IPv4 address ("192.168.1.20:47100"), or an IPv6 address, bracketed
/// ("[::1]:47100", the brackets removed) or bare ("::1:47100": the last colon separates the port). PORT is 1 to 5
/// decimal digits, 1..65535. No whitespace, no empty HOST.
/// @return the address, or nullopt for anything else ("localhost", "localhost:0", "host:99999", ":47100", "a b:1").
/// Cost: O(length).
std::optional<HostAddress> parseHostAddress(const QString& text);

}  // namespace sc::app
