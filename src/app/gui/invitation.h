#pragma once
// An invitation to a hosted session, as Session → Copy Invitation puts it on the clipboard: the address and TCP
// port, the host's certificate fingerprint, and the command line a peer runs to join with that fingerprint pinned
// (`shapecast --join HOST:PORT --fingerprint HEX`, launch_options.cpp). Never the password. Pure text.

#include <QByteArray>
#include <QString>
#include <QtGlobal>

namespace sc::app {

/// Three lines: "ShapeCast session at ADDRESS:PORT", "Certificate fingerprint: AB:CD:…" and
/// "Join with: shapecast --join ADDRESS:PORT --fingerprint abcd…" (IPv6 addresses bracketed). Empty when the
/// fingerprint or the port is missing.
QString invitationText(const QString& address, quint16 port, const QByteArray& fingerprint);

/// The address peers most likely reach this computer at: its first non-loopback IPv4 address that is up, else
/// its first IPv6 one, else 127.0.0.1. Cost: one interface enumeration.
QString reachableAddress();

}  // namespace sc::app
