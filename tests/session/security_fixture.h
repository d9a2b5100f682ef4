#pragma once
// The fixture of session_security_tests' loopback suites (security_*_test.cpp): a generated mesh (icosphere, 162
// vertices) with a 20-function harmonic basis and one TLS identity shared by the suite, a password-protected host on
// 127.0.0.1 that sends frames all the time, and clients of it.

#include "harmonic_host_model.h"
#include "loopback_session.h"
#include "session/net/session_client.h"
#include "session/net/session_host.h"
#include "session/net/tls_identity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QtCore/QString>

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <utility>

namespace sc::session {

using testing::kWaitMs;

/// The session password of the Security fixture's host and clients.
inline const QString kPassword = QStringLiteral("correct horse battery staple");

class Security : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_model = testing::harmonicHostModel(sc::testing::icosphere(2), 20);
    ASSERT_EQ(s_model->rowCount(), 20);
    s_identity = std::make_shared<const TlsIdentity>(*generateTlsIdentity(QStringLiteral("test host")));
  }
  static void TearDownTestSuite() {
    s_model.reset();
    s_identity.reset();
  }

  /// 127.0.0.1, `password` (none: open), 1000 PBKDF2 iterations, the suite's identity, a refresh frame every 50 ms.
  static SessionHostOptions hostOptions(std::optional<QString> password = kPassword) {
    SessionHostOptions options;
    options.address = QHostAddress::LocalHost;
    options.password = std::move(password);
    options.pbkdf2Iterations = 1000;
    options.hostName = QStringLiteral("Hostess");
    options.identity = s_identity;
    options.idleRefresh = std::chrono::milliseconds(50);  // frames flow all the time
    return options;
  }
  /// A started host of the suite's model (a failed start is a test failure).
  static std::unique_ptr<SessionHost> startHost(SessionHostOptions options = hostOptions()) {
    return testing::startHost(s_model, std::move(options));
  }
  /// Options that join 127.0.0.1:`port` as `name` with `password`.
  static SessionClientOptions clientOptions(quint16 port, const QString& name,
                                            std::optional<QString> password = kPassword) {
    return testing::clientOptions(port, name, std::move(password));
  }
  static std::unique_ptr<SessionClient> start(SessionClientOptions options) {
    return testing::startClient(std::move(options));
  }
  /// Waits until Ready, Failed or Left; true when Ready.
  static bool settle(SessionClient& client) { return testing::settle(client); }
  /// The host's peers other than itself.
  static std::size_t members(const SessionHost& host) { return host.peerList().peers.size() - 1; }

  static inline std::shared_ptr<const HostModel> s_model;
  static inline std::shared_ptr<const TlsIdentity> s_identity;
};

}  // namespace sc::session
