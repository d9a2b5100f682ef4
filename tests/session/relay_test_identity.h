#pragma once
// Two TLS identities for the relay suites (issue 18), generated once per process: 0 the host's, 1 another key.
#include "session/net/tls_identity.h"

namespace sc::session::testing {

inline const TlsIdentity& relayIdentity(int which = 0) {
  static const TlsIdentity host = *generateTlsIdentity(QStringLiteral("relay-host"));
  static const TlsIdentity other = *generateTlsIdentity(QStringLiteral("relay-other"));
  return which == 0 ? host : other;
}

}  // namespace sc::session::testing
