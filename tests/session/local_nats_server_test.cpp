// The local nats-server fixture (src/session/net/local_nats_server.h, issue 18): its configuration, start with a
// random loopback port read from the ports file, a client connecting with the generated users, stop by PID, and
// a restart on the same port.
#include "session/net/local_nats_server.h"
#include "session/net/nats_client.h"

#include <gtest/gtest.h>

#include <QtCore/QDir>
#include <QtCore/QFile>
#include <QtCore/QFileInfo>

#include <csignal>

namespace sc::session {
namespace {

TEST(NatsServerConfigText, UsesAPlainAuthorizationBlockAndTheSessionsSubjects) {
  NatsServerConfig config;
  config.sessionId = QStringLiteral("abc");
  const QString text = natsServerConfigText(config, 0, QStringLiteral("/tmp/x/js"));
  EXPECT_TRUE(text.contains(QStringLiteral("listen: 127.0.0.1:-1")));
  EXPECT_TRUE(text.contains(QStringLiteral("store_dir: \"/tmp/x/js\"")));
  EXPECT_TRUE(text.contains(QStringLiteral("authorization {")));
  EXPECT_FALSE(text.contains(QStringLiteral("accounts")));  // advisory GHSA-fr2g-9hjm-wr23: never mixed
  EXPECT_TRUE(text.contains(QStringLiteral("subscribe: [\"sc.abc.z\", \"_INBOX.>\"]")));
  EXPECT_TRUE(natsServerConfigText(config, 4222, QStringLiteral("/j")).contains(QStringLiteral("127.0.0.1:4222")));
}

class NatsServerFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
  }
};

TEST_F(NatsServerFixture, StartsOnARandomLoopbackPortAcceptsItsUsersAndStopsByPid) {
  LocalNatsServer server;
  QString error;
  ASSERT_TRUE(server.start(&error)) << error.toStdString();
  EXPECT_TRUE(server.running());
  EXPECT_GT(server.port(), 0);
  EXPECT_EQ(server.url(), QStringLiteral("nats://127.0.0.1:%1").arg(server.port()));
  EXPECT_GT(server.pid(), 0);
  EXPECT_EQ(::kill(static_cast<pid_t>(server.pid()), 0), 0);  // alive
  {
    NatsConnectOptions options;
    options.url = server.url();
    options.user = server.config().viewerUser;
    options.password = server.config().viewerPassword;
    QString why;
    auto viewer = NatsConnection::connect(options, &why);
    ASSERT_TRUE(viewer) << why.toStdString();
    EXPECT_TRUE(viewer->connected());
    options.password = QStringLiteral("wrong");
    EXPECT_FALSE(NatsConnection::connect(options, &why));
  }
  const qint64 pid = server.pid();
  server.stop();
  EXPECT_FALSE(server.running());
  EXPECT_NE(::kill(static_cast<pid_t>(pid), 0), 0);  // gone (reaped by QProcess)
  EXPECT_TRUE(QFileInfo(QDir(server.directory()).filePath(QStringLiteral("nats.conf"))).exists());
}

TEST_F(NatsServerFixture, RestartsOnTheSamePort) {
  LocalNatsServer server;
  QString error;
  ASSERT_TRUE(server.start(&error)) << error.toStdString();
  const int port = server.port();
  const qint64 pid = server.pid();
  ASSERT_TRUE(server.restart(&error)) << error.toStdString();
  EXPECT_EQ(server.port(), port);
  EXPECT_NE(server.pid(), pid);
}

TEST(NatsServerConfigText, WritesATlsBlockOnlyWithTls) {
  NatsServerConfig config;
  EXPECT_FALSE(
      natsServerConfigText(config, 0, QStringLiteral("/j"), QStringLiteral("/t")).contains(QStringLiteral("tls {")));
  config.tls = NatsServerTls::CaSigned;
  const QString text = natsServerConfigText(config, 0, QStringLiteral("/j"), QStringLiteral("/t"));
  EXPECT_TRUE(text.contains(QStringLiteral("tls {"))) << text.toStdString();
  EXPECT_TRUE(text.contains(QStringLiteral("cert_file: \"/t/server-cert.pem\""))) << text.toStdString();
  EXPECT_TRUE(text.contains(QStringLiteral("key_file: \"/t/server-key.pem\""))) << text.toStdString();
}

TEST_F(NatsServerFixture, ASelfSignedServerAcceptsClientsThatTrustItsCertificateAndKeepsItOnRestart) {
  LocalNatsServer server;
  server.setTls(NatsServerTls::SelfSigned);
  QString error;
  ASSERT_TRUE(server.start(&error)) << error.toStdString();
  EXPECT_EQ(server.url(), QStringLiteral("tls://127.0.0.1:%1").arg(server.port()));
  QFile ca(server.caFile());
  ASSERT_TRUE(ca.open(QIODevice::ReadOnly)) << server.caFile().toStdString();
  const QByteArray certificate = ca.readAll();
  ca.close();
  EXPECT_TRUE(certificate.startsWith("-----BEGIN CERTIFICATE-----"));
  EXPECT_EQ(QFile(QDir(server.directory()).filePath(QStringLiteral("server-key.pem"))).permissions() &
                (QFile::ReadGroup | QFile::ReadOther),
            QFile::Permissions());  // the key is the owner's only
  NatsConnectOptions options;
  options.url = server.url();
  options.user = server.config().viewerUser;
  options.password = server.config().viewerPassword;
  options.caFile = server.caFile();
  QString why;
  EXPECT_TRUE(NatsConnection::connect(options, &why)) << why.toStdString();
  options.caFile.clear();  // the system's CAs do not know it
  EXPECT_FALSE(NatsConnection::connect(options, &why));
  EXPECT_TRUE(why.contains(QStringLiteral("TLS"))) << why.toStdString();
  options.caFile = QDir(server.directory()).filePath(QStringLiteral("nats.conf"));  // not a certificate
  EXPECT_FALSE(NatsConnection::connect(options, &why));
  EXPECT_TRUE(why.contains(QStringLiteral("cannot load the CA file"))) << why.toStdString();

  ASSERT_TRUE(server.restart(&error)) << error.toStdString();
  ASSERT_TRUE(ca.open(QIODevice::ReadOnly));
  EXPECT_EQ(ca.readAll(), certificate);  // the same certificate: clients keep trusting it
  options.caFile = server.caFile();
  EXPECT_TRUE(NatsConnection::connect(options, &why)) << why.toStdString();
}

}  // namespace
}  // namespace sc::session
