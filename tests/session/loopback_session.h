#pragma once
// The steps the loopback suites share (session_loopback_tests, session_security_tests): a SessionHost started on
// 127.0.0.1, SessionClient options for it, a started client, and waiting until a client is Ready or has ended.

#include "session/engine/host_model.h"
#include "session/net/session_client.h"
#include "session/net/session_host.h"

#include <QtCore/QString>

#include <memory>
#include <optional>

namespace sc::session::testing {

/// A generous upper bound for one awaited condition; conditions usually hold in milliseconds.
inline constexpr int kWaitMs = 8000;
/// PBKDF2 iterations of the loopback and security fixtures' hosts (fast joins); clientOptions() lets its clients
/// answer them (below kMinPbkdf2Iterations, which real clients refuse).
inline constexpr std::uint32_t kTestPbkdf2Iterations = 1000;

/// Creates a SessionHost of `model` with `options` and starts it; a failed start is a test failure (EXPECT, with
/// the host's error) and the host is returned anyway. Cost: binding the sockets, building the first level.
std::unique_ptr<SessionHost> startHost(std::shared_ptr<const HostModel> model, SessionHostOptions options);

/// Options that join 127.0.0.1:`port` as `name`, with `password` (none: an open session) and everything else at
/// SessionClientOptions' defaults (the full model, no pinned fingerprint and no trust on first use) but for
/// minPbkdf2Iterations = kTestPbkdf2Iterations.
SessionClientOptions clientOptions(quint16 port, const QString& name, std::optional<QString> password = std::nullopt);

/// Creates a SessionClient with `options` and starts it (the connection is made by the event loop).
std::unique_ptr<SessionClient> startClient(SessionClientOptions options);

/// Processes events until `client` is Ready (it has its level), Failed or Left, at most kWaitMs; true when Ready.
bool settle(SessionClient& client);

}  // namespace sc::session::testing
