// TLS to the broker (issue 18; docs/security.md "TLS to the broker"): a nats-server that requires TLS with a
// certificate signed by a generated CA (LocalNatsServer, NatsServerTls::CaSigned). The host and viewers trusting
// that CA (NatsConnectOptions::caFile, what --nats-ca gives) get every frame over tls://; a viewer that trusts
// another CA, or only the system's, is refused with a readable error. Fixture: relay_nats_fixture.h.
#include "relay_nats_fixture.h"

#include <algorithm>
#include <memory>
#include <optional>

#include <QtCore/QFile>
#include <QtCore/QTemporaryDir>

namespace sc::session {
namespace {

class RelayNatsTls : public RelayNats {
 protected:
  void configureServer(LocalNatsServer& server) override { server.setTls(NatsServerTls::CaSigned); }
};

TEST_F(RelayNatsTls, AHostAndViewersOverTlsGetEveryFrame) {
  ASSERT_TRUE(m_server.url().startsWith(QStringLiteral("tls://127.0.0.1:"))) << m_server.url().toStdString();
  for (int i = 0; i < 2; ++i) ASSERT_NE(addViewer(), nullptr);
  const std::uint32_t first = m_host->currentFrame();
  for (int step = 1; step <= 10; ++step) dragOnce(0.01 * step);
  ASSERT_GE(m_host->currentFrame(), first + 10);
  ASSERT_TRUE(waitFor([&] {
    return std::all_of(m_viewers.begin(), m_viewers.end(), [&](const auto& viewer) { return caughtUp(*viewer); });
  }));
  for (const auto& viewer : m_viewers) {
    EXPECT_EQ(viewer->stats().lost, 0);
    EXPECT_GE(viewer->stats().applied, 10);
    EXPECT_EQ(viewer->receiver().coefficients(), m_host->coefficients());
  }
  EXPECT_EQ(m_publisher->counters().failures, 0);
}

TEST_F(RelayNatsTls, AViewerTrustingAnotherCaIsRefusedReadably) {
  CertificateProfile authority;
  authority.commonName = QStringLiteral("another CA");
  authority.certificateAuthority = true;
  const std::optional<TlsIdentity> other = generateTlsIdentity(authority, nullptr);
  ASSERT_TRUE(other);
  QTemporaryDir dir;
  const QString otherCa = dir.filePath(QStringLiteral("other-ca.pem"));
  {
    QFile file(otherCa);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(other->certificate.toPem());
  }
  NatsConnectOptions options = viewerCredential();
  options.caFile = otherCa;
  QString error;
  EXPECT_FALSE(NatsConnection::connect(options, &error));
  EXPECT_TRUE(error.startsWith(QStringLiteral("TLS to the NATS server at tls://127.0.0.1:"))) << error.toStdString();
  EXPECT_TRUE(error.contains(QStringLiteral("not signed by the trusted CA in ") + otherCa)) << error.toStdString();

  // A viewer (the whole RelayViewer) with the system's CAs only is refused as well, and says so.
  RelayViewerOptions viewer;
  viewer.nats = viewerCredential();
  viewer.nats.caFile.clear();
  viewer.sessionId = m_server.config().sessionId;
  viewer.pin = m_host->fingerprint();
  RelayViewer refused(std::move(viewer));
  error.clear();
  EXPECT_FALSE(refused.start(&error));
  EXPECT_TRUE(error.contains(QStringLiteral("TLS"))) << error.toStdString();

  // The same URL without tls:// : the server requires TLS, so the client switches to it and verifies the same way.
  options = viewerCredential();
  options.url.replace(QStringLiteral("tls://"), QStringLiteral("nats://"));
  std::unique_ptr<NatsConnection> upgraded = NatsConnection::connect(options, &error);
  EXPECT_TRUE(upgraded) << error.toStdString();
}

}  // namespace
}  // namespace sc::session
