// Security of the control channel (docs/security.md): it is ciphertext on the wire (an on-path relay sees no name,
// key, token or model byte), a plaintext client gets nothing readable, a wrong pinned fingerprint is refused with a
// clear reason, trust on first use refuses a changed certificate, and the password proof bound to the host's
// certificate keeps out a relaying man in the middle even when the client accepts the relay's certificate. Real TLS
// over loopback sockets. Fixture: security_fixture.h.
#include "security_fixture.h"

#include "session/net/tls_known_hosts.h"
#include "session/net/tls_server.h"
#include "session/wire/control_frame.h"

#include <QtCore/QTemporaryDir>
#include <QtNetwork/QSslSocket>
#include <QtNetwork/QTcpServer>
#include <QtTest/QTest>

namespace sc::session {
namespace {

// --- relays: what an on-path observer sees (Plain) and a man in the middle the client trusts (Tls)

class Relay {
 public:
  enum class Mode { Plain, Tls };
  Relay(Mode mode, quint16 hostPort) : m_mode(mode), m_hostPort(hostPort) {
    if (mode == Mode::Tls) {
      m_identity = generateTlsIdentity(QStringLiteral("relay"));
      auto* tls = new TlsServer(&m_owner);
      tls->setSslConfiguration(hostTlsConfiguration(m_identity->certificate, m_identity->privateKey));
      m_server = tls;
    } else {
      m_server = new QTcpServer(&m_owner);
    }
    QObject::connect(m_server, &QTcpServer::newConnection, &m_owner, [this] { accept(); });
    m_server->listen(QHostAddress::LocalHost);
  }
  [[nodiscard]] quint16 port() const { return m_server->serverPort(); }
  [[nodiscard]] QByteArray fingerprint() const { return m_identity ? m_identity->fingerprint() : QByteArray(); }
  QByteArray toHost;    ///< every byte the client side sent, as the relay read it
  QByteArray toClient;  ///< every byte the host side sent, as the relay read it

 private:
  void accept() {
    while (QTcpSocket* down = m_server->nextPendingConnection()) {
      QTcpSocket* up = nullptr;
      if (m_mode == Mode::Tls) {
        auto* tls = new QSslSocket(&m_owner);
        tls->setSslConfiguration(clientTlsConfiguration());
        tls->connectToHostEncrypted(QStringLiteral("127.0.0.1"), m_hostPort);
        up = tls;
      } else {
        up = new QTcpSocket(&m_owner);
        up->connectToHost(QHostAddress::LocalHost, m_hostPort);
      }
      QObject::connect(down, &QTcpSocket::readyRead, up, [this, down, up] {
        const QByteArray bytes = down->readAll();
        toHost += bytes;
        up->write(bytes);
      });
      QObject::connect(up, &QTcpSocket::readyRead, down, [this, down, up] {
        const QByteArray bytes = up->readAll();
        toClient += bytes;
        down->write(bytes);
      });
      QObject::connect(down, &QTcpSocket::disconnected, up, &QTcpSocket::disconnectFromHost);
      QObject::connect(up, &QTcpSocket::disconnected, down, &QTcpSocket::disconnectFromHost);
    }
  }

  Mode m_mode;
  quint16 m_hostPort;
  std::optional<TlsIdentity> m_identity;
  QObject m_owner;
  QTcpServer* m_server = nullptr;
};

/// A TLS record header starts with its content type (0x16 handshake, 0x15 alert, 0x17 data) and 0x03 (version).
bool startsWithTlsRecord(const QByteArray& bytes) {
  return bytes.size() >= 5 && (bytes[0] == 0x16 || bytes[0] == 0x15 || bytes[0] == 0x17) && bytes[1] == 0x03;
}

TEST_F(Security, ControlChannelIsCiphertextOnTheWire) {
  auto host = startHost();
  Relay observer(Relay::Mode::Plain, host->tcpPort());
  auto client = start(clientOptions(observer.port(), QStringLiteral("Observed Zoë")));
  ASSERT_TRUE(settle(*client)) << client->errorText().toStdString();
  EXPECT_EQ(client->hostFingerprint(), host->fingerprint());
  ASSERT_TRUE(startsWithTlsRecord(observer.toHost));
  ASSERT_TRUE(startsWithTlsRecord(observer.toClient));
  EXPECT_EQ(observer.toHost[0], 0x16);  // ClientHello
  // What a plaintext channel would show: names, the datagram key and path token of the Welcome, the model.
  ASSERT_TRUE(client->session());
  const QByteArray everything = observer.toHost + observer.toClient;
  EXPECT_FALSE(everything.contains(QStringLiteral("Observed Zoë").toUtf8()));
  EXPECT_FALSE(everything.contains(QByteArrayLiteral("Hostess")));
  EXPECT_FALSE(everything.contains(client->session()->datagramKey));
  EXPECT_FALSE(everything.contains(client->session()->pathToken));
  ASSERT_GE(client->levelPayload().size(), 64);
  EXPECT_FALSE(everything.contains(client->levelPayload().left(32)));
  EXPECT_FALSE(everything.contains(client->levelPayload().right(32)));
  EXPECT_GT(observer.toClient.size(), client->levelPayload().size());  // the model did cross this relay
}

TEST_F(Security, PlaintextClientGetsNothingReadableAndIsClosed) {
  auto host = startHost(hostOptions(std::nullopt));  // even an open session speaks only TLS
  QTcpSocket plain;
  QByteArray received;
  QObject::connect(&plain, &QTcpSocket::readyRead, &plain, [&] { received += plain.readAll(); });
  plain.connectToHost(QHostAddress::LocalHost, host->tcpPort());
  ASSERT_TRUE(plain.waitForConnected(kWaitMs));
  plain.write(encodeControlMessage(Hello{kProtocolVersion, QStringLiteral("plain")}));
  ASSERT_TRUE(QTest::qWaitFor([&] { return plain.state() == QAbstractSocket::UnconnectedState; }, kWaitMs));
  EXPECT_TRUE(received.isEmpty() || startsWithTlsRecord(received)) << received.toHex().toStdString();
  ControlFrameReader reader;
  reader.append(received);
  while (const auto result = reader.next()) EXPECT_NE(result->error, ControlError::None);  // no Welcome, no Refused
  EXPECT_GE(host->counters().tlsFailures, 1u);
  EXPECT_EQ(members(*host), 0u);
}

TEST_F(Security, WrongFingerprintIsRefusedWithAClearReasonRightOneJoins) {
  auto host = startHost();
  SessionClientOptions pinned = clientOptions(host->tcpPort(), QStringLiteral("pinned"));
  pinned.fingerprint = QByteArray(kFingerprintSize, '\x5a');
  auto wrong = start(pinned);
  EXPECT_FALSE(settle(*wrong));
  EXPECT_TRUE(wrong->errorText().contains(QStringLiteral("fingerprint"))) << wrong->errorText().toStdString();
  EXPECT_TRUE(wrong->errorText().contains(formatFingerprint(host->fingerprint())));
  EXPECT_EQ(wrong->handshake().state(), ClientHandshake::State::SendHello);  // no Hello: nothing was sent
  pinned.fingerprint = host->fingerprint();
  auto right = start(pinned);
  EXPECT_TRUE(settle(*right)) << right->errorText().toStdString();
  EXPECT_EQ(members(*host), 1u);
}

TEST_F(Security, TrustOnFirstUseRemembersAndRefusesAChangedCertificate) {
  QTemporaryDir temp;
  ASSERT_TRUE(temp.isValid());
  const QString store = temp.filePath(QStringLiteral("known.ini"));
  auto host = startHost();
  SessionClientOptions options = clientOptions(host->tcpPort(), QStringLiteral("tofu"));
  options.trustOnFirstUse = true;
  options.knownHostsFile = store;
  auto first = start(options);
  ASSERT_TRUE(settle(*first)) << first->errorText().toStdString();
  EXPECT_EQ(KnownHosts(store).lookup(options.host, options.port), host->fingerprint());
  first->leave();
  // Another certificate at the same address (a new host key, or an impostor): refused, nothing replaced.
  const QByteArray other(kFingerprintSize, '\x77');
  KnownHosts(store).remember(options.host, options.port, other);
  options.name = QStringLiteral("tofu2");
  auto second = start(options);
  EXPECT_FALSE(settle(*second));
  EXPECT_TRUE(second->errorText().contains(QStringLiteral("changed"))) << second->errorText().toStdString();
  EXPECT_EQ(KnownHosts(store).lookup(options.host, options.port), other);
  // Pinning the new fingerprint explicitly accepts it and updates the entry.
  options.fingerprint = host->fingerprint();
  options.name = QStringLiteral("tofu3");
  auto third = start(options);
  EXPECT_TRUE(settle(*third)) << third->errorText().toStdString();
  EXPECT_EQ(KnownHosts(store).lookup(options.host, options.port), host->fingerprint());
}

TEST_F(Security, TheHostKeepsOnlyTheDerivedKeyNotThePassword) {
  // The host kept options().password for its whole life after deriving the key once.
  auto host = startHost();
  EXPECT_FALSE(host->options().password.has_value());
  auto member = start(clientOptions(host->tcpPort(), QStringLiteral("member")));
  EXPECT_TRUE(settle(*member)) << member->errorText().toStdString();
}

TEST_F(Security, RelayingManInTheMiddleCannotGetInEvenWhenTheClientAcceptsItsCertificate) {
  auto host = startHost();
  Relay mitm(Relay::Mode::Tls, host->tcpPort());
  auto victim = start(clientOptions(mitm.port(), QStringLiteral("victim")));  // no pin: accepts the relay's cert
  EXPECT_FALSE(settle(*victim));
  EXPECT_EQ(victim->hostFingerprint(), mitm.fingerprint());
  EXPECT_TRUE(victim->errorText().contains(QStringLiteral("wrong password"))) << victim->errorText().toStdString();
  EXPECT_TRUE(mitm.toHost.contains(QByteArrayLiteral("victim")));  // the relay does see the clear text
  EXPECT_EQ(host->counters().refusalsFor(RefuseReason::WrongPassword), 1u);
  EXPECT_EQ(members(*host), 0u);
  EXPECT_FALSE(mitm.toClient.contains(QByteArrayLiteral("Hostess")));  // no PeerList, no model ever reached it
  // The same client and password straight to the host join: the relay, not the password, was refused.
  auto direct = start(clientOptions(host->tcpPort(), QStringLiteral("victim")));
  EXPECT_TRUE(settle(*direct)) << direct->errorText().toStdString();
  // A pinned client notices the relay before sending anything.
  SessionClientOptions pinned = clientOptions(mitm.port(), QStringLiteral("careful"));
  pinned.fingerprint = host->fingerprint();
  auto careful = start(pinned);
  EXPECT_FALSE(settle(*careful));
  EXPECT_TRUE(careful->errorText().contains(QStringLiteral("fingerprint")));
}

}  // namespace
}  // namespace sc::session
