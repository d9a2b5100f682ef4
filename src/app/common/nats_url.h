#pragma once
// The NATS server URL a user types, for `shapecast --host … --nats URL`, `--watch URL`, the Host… dialog's relay
// group and `shapecast-cli host|watch --nats URL` alike (issue 18; README "Viewers through NATS").

#include <QString>

namespace sc::app {

/// Empty when `urls` is one or several comma-separated NATS server URLs, each nats://HOST[:PORT] or
/// tls://HOST[:PORT] (HOST a name or an IPv4 address, or a bracketed IPv6 one; PORT 1..65535; no user or password
/// in the URL, no path). Otherwise one readable sentence naming the URL and the problem. Cost: O(length).
QString natsUrlProblem(const QString& urls);

}  // namespace sc::app
