// Security of the control channel and of what a stranger can do (docs/security.md, each claim names its test
// here): the TLS identity and fingerprints, pinning and trust on first use, the password proof bound to the host's
// certificate (a relaying man in the middle is refused), the control channel is ciphertext on the wire, limits on
// message sizes and on unauthenticated connections, and a stranger can neither join, see the model, move it, nor
// get a datagram out of the host. Real TLS over loopback sockets (127.0.0.1; 127.0.0.2 as "another address").
#include "session/session_client.h"
#include "session/session_host.h"

#include <gtest/gtest.h>

#include <QtCore/QFile>
#include <QtCore/QTemporaryDir>
#include <QtCore/QtEndian>
#include <QtNetwork/QNetworkDatagram>
#include <QtNetwork/QSslSocket>
#include <QtNetwork/QUdpSocket>
#include <QtTest/QTest>

#include "harmonic_host_model.h"
#include "raw_control_peer.h"
#include "session/host_datagram_channel.h"
#include "session/path_open.h"
#include "session/tls_identity.h"
#include "session/tls_known_hosts.h"
#include "session/tls_server.h"
#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"
#include "test_meshes.h"

#include <memory>
#include <vector>

namespace sc::session {
namespace {

constexpr int kWaitMs = 8000;
const QString kPassword = QStringLiteral("correct horse battery staple");

// --- identity, fingerprints, trust decisions (no sockets)

TEST(TlsIdentity, GeneratedCertificateHasAStableSha256Fingerprint) {
  QString error;
  const std::optional<TlsIdentity> a = generateTlsIdentity(QStringLiteral("test"), &error);
  ASSERT_TRUE(a) << error.toStdString();
  EXPECT_FALSE(a->certificate.isNull());
  EXPECT_FALSE(a->privateKey.isNull());
  EXPECT_EQ(a->fingerprint().size(), kFingerprintSize);
  EXPECT_EQ(a->fingerprint(), a->certificate.digest(QCryptographicHash::Sha256));
  EXPECT_TRUE(a->certificate.isSelfSigned());
  const std::optional<TlsIdentity> b = generateTlsIdentity(QStringLiteral("test"));
  ASSERT_TRUE(b);
  EXPECT_NE(a->fingerprint(), b->fingerprint());  // fresh key each time
}

TEST(TlsIdentity, StoredOnFirstUseWithOwnerOnlyPermissionsAndReused) {
  QTemporaryDir temp;
  ASSERT_TRUE(temp.isValid());
  const QString dir = temp.filePath(QStringLiteral("tls"));
  QString error;
  const std::optional<TlsIdentity> first = loadOrCreateTlsIdentity(dir, &error);
  ASSERT_TRUE(first) << error.toStdString();
  const QString keyPath = dir + QStringLiteral("/host-key.pem");
  ASSERT_TRUE(QFile::exists(keyPath));
  const QFile::Permissions groupOrOther =
      QFile::ReadGroup | QFile::WriteGroup | QFile::ExeGroup | QFile::ReadOther | QFile::WriteOther | QFile::ExeOther;
  EXPECT_EQ(QFile::permissions(keyPath) & groupOrOther, QFile::Permissions());  // 0600: the owner only
  EXPECT_TRUE(QFile::permissions(keyPath) & QFile::ReadOwner);
  const std::optional<TlsIdentity> second = loadOrCreateTlsIdentity(dir, &error);
  ASSERT_TRUE(second) << error.toStdString();
  EXPECT_EQ(second->fingerprint(), first->fingerprint());
  // A key that does not belong to the certificate is refused, not silently replaced.
  const std::optional<TlsIdentity> other = generateTlsIdentity(QStringLiteral("other"));
  ASSERT_TRUE(other);
  QFile key(keyPath);
  ASSERT_TRUE(key.open(QIODevice::WriteOnly | QIODevice::Truncate));
  key.write(other->privateKey.toPem());
  key.close();
  EXPECT_FALSE(loadOrCreateTlsIdentity(dir, &error));
  EXPECT_FALSE(error.isEmpty());
}

TEST(TlsIdentity, FingerprintsFormatAndParse) {
  const QByteArray fingerprint =
      QByteArray::fromHex("00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff");
  const QString text = formatFingerprint(fingerprint);
  EXPECT_EQ(text.left(9), QStringLiteral("00:11:22:"));
  EXPECT_EQ(parseFingerprint(text), fingerprint);
  EXPECT_EQ(parseFingerprint(text.toLower().remove(QLatin1Char(':'))), fingerprint);
  EXPECT_FALSE(parseFingerprint(text.left(text.size() - 1)));
  EXPECT_FALSE(parseFingerprint(QStringLiteral("zz") + text.mid(2)));
  EXPECT_FALSE(parseFingerprint(QString()));
}

TEST(TrustDecision, PinnedThenKnownThenFirstUse) {
  using V = FingerprintCheck::Verdict;
  const QByteArray a(32, '\x0a');
  const QByteArray b(32, '\x0b');
  EXPECT_EQ(checkFingerprint(a, a, std::nullopt, true).verdict, V::Pinned);
  const FingerprintCheck mismatch = checkFingerprint(a, b, a, true);  // a pin wins over the remembered entry
  EXPECT_EQ(mismatch.verdict, V::Mismatch);
  EXPECT_FALSE(mismatch.accepted());
  EXPECT_TRUE(mismatch.reason.contains(formatFingerprint(a)) && mismatch.reason.contains(formatFingerprint(b)));
  EXPECT_EQ(checkFingerprint(a, {}, a, true).verdict, V::Known);
  const FingerprintCheck changed = checkFingerprint(a, {}, b, true);
  EXPECT_EQ(changed.verdict, V::Changed);
  EXPECT_FALSE(changed.accepted());
  EXPECT_TRUE(changed.reason.contains(QStringLiteral("changed")));
  EXPECT_EQ(checkFingerprint(a, {}, std::nullopt, true).verdict, V::FirstUse);
  EXPECT_EQ(checkFingerprint(a, {}, std::nullopt, false).verdict, V::Untrusted);
}

TEST(TrustDecision, KnownHostsRememberPerHostAndPort) {
  QTemporaryDir temp;
  ASSERT_TRUE(temp.isValid());
  KnownHosts hosts(temp.filePath(QStringLiteral("known.ini")));
  const QByteArray a(32, '\x0a');
  EXPECT_FALSE(hosts.lookup(QStringLiteral("::1"), 47100));
  hosts.remember(QStringLiteral("::1"), 47100, a);
  hosts.remember(QStringLiteral("example.org"), 47100, QByteArray(32, '\x0b'));
  EXPECT_EQ(hosts.lookup(QStringLiteral("::1"), 47100), a);
  EXPECT_FALSE(hosts.lookup(QStringLiteral("::1"), 47101));
  EXPECT_EQ(KnownHosts(temp.filePath(QStringLiteral("known.ini"))).lookup(QStringLiteral("::1"), 47100), a);
  hosts.forget(QStringLiteral("::1"), 47100);
  EXPECT_FALSE(hosts.lookup(QStringLiteral("::1"), 47100));
  EXPECT_TRUE(hosts.lookup(QStringLiteral("example.org"), 47100));
}

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

// --- sessions over loopback

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
  static std::unique_ptr<SessionHost> startHost(SessionHostOptions options = hostOptions()) {
    auto host = std::make_unique<SessionHost>(s_model, std::move(options));
    QString error;
    EXPECT_TRUE(host->start(&error)) << error.toStdString();
    return host;
  }
  static SessionClientOptions clientOptions(quint16 port, const QString& name,
                                            std::optional<QString> password = kPassword) {
    SessionClientOptions options;
    options.host = QStringLiteral("127.0.0.1");
    options.port = port;
    options.name = name;
    options.password = std::move(password);
    return options;
  }
  static std::unique_ptr<SessionClient> start(SessionClientOptions options) {
    auto client = std::make_unique<SessionClient>(std::move(options));
    client->start();
    return client;
  }
  /// Waits until Ready, Failed or Left; true when Ready.
  static bool settle(SessionClient& client) {
    (void)QTest::qWaitFor(
        [&] {
          const auto s = client.state();
          return s == SessionClient::State::Ready || s == SessionClient::State::Failed ||
                 s == SessionClient::State::Left;
        },
        kWaitMs);
    return client.state() == SessionClient::State::Ready;
  }
  static std::size_t members(const SessionHost& host) { return host.peerList().peers.size() - 1; }

  static std::shared_ptr<const HostModel> s_model;
  static std::shared_ptr<const TlsIdentity> s_identity;
};
std::shared_ptr<const HostModel> Security::s_model;
std::shared_ptr<const TlsIdentity> Security::s_identity;

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

TEST_F(Security, OversizedMessageClosesThatConnectionAndTheHostKeepsServing) {
  auto host = startHost(hostOptions(std::nullopt));
  auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest"), std::nullopt));
  ASSERT_TRUE(settle(*honest)) << honest->errorText().toStdString();
  QByteArray header(5, '\0');
  qToBigEndian<quint32>(kMaxControlMessageSize + 1, header.data());
  header[4] = 0x10;
  // Before the Welcome and after it.
  testing::RawControlPeer early(host->tcpPort());
  ASSERT_TRUE(early.connected());
  early.sendRaw(header);
  EXPECT_TRUE(early.closedByHost());
  testing::RawControlPeer member(host->tcpPort());
  ASSERT_TRUE(member.join(QStringLiteral("member")));
  member.sendRaw(header + QByteArray(64 * 1024, 'x'));
  EXPECT_TRUE(member.closedByHost());
  EXPECT_EQ(host->counters().oversizeMessages, 2u);
  const std::uint64_t applied = honest->channel().framesApplied();
  EXPECT_TRUE(QTest::qWaitFor([&] { return honest->channel().framesApplied() > applied + 3; }, kWaitMs));
  EXPECT_EQ(honest->state(), SessionClient::State::Ready);
  auto later = start(clientOptions(host->tcpPort(), QStringLiteral("later"), std::nullopt));
  EXPECT_TRUE(settle(*later)) << later->errorText().toStdString();
}

/// Opens `count` TCP connections from `source` to the host that never start TLS.
std::vector<std::unique_ptr<QTcpSocket>> flood(const QHostAddress& source, quint16 port, int count) {
  std::vector<std::unique_ptr<QTcpSocket>> sockets;
  for (int i = 0; i < count; ++i) {
    auto socket = std::make_unique<QTcpSocket>();
    socket->bind(source);
    socket->connectToHost(QHostAddress::LocalHost, port);
    sockets.push_back(std::move(socket));
  }
  return sockets;
}

int stillOpen(const std::vector<std::unique_ptr<QTcpSocket>>& sockets) {
  return static_cast<int>(std::count_if(sockets.begin(), sockets.end(),
                                        [](const auto& s) { return s->state() != QAbstractSocket::UnconnectedState; }));
}

TEST_F(Security, ConnectionsOverThePerAddressLimitAreClosedWhileAnHonestClientJoins) {
  SessionHostOptions options = hostOptions();
  options.maxPendingPerAddress = 4;
  auto host = startHost(options);
  const auto sockets = flood(QHostAddress(QStringLiteral("127.0.0.2")), host->tcpPort(), 10);
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().connectionsOverLimit == 6; }, kWaitMs));
  EXPECT_TRUE(QTest::qWaitFor([&] { return stillOpen(sockets) == 4; }, kWaitMs));
  auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest")));
  EXPECT_TRUE(settle(*honest)) << honest->errorText().toStdString();
  EXPECT_EQ(stillOpen(sockets), 4);  // the admitted ones wait for their deadline
}

TEST_F(Security, PendingConnectionsAreCappedAndClosedAtTheHandshakeDeadline) {
  SessionHostOptions options = hostOptions();
  options.maxPendingHandshakes = 3;
  options.handshakeTimeout = std::chrono::milliseconds(1000);
  auto host = startHost(options);
  const auto sockets = flood(QHostAddress(QStringLiteral("127.0.0.2")), host->tcpPort(), 5);
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->counters().connectionsOverLimit == 2; }, kWaitMs));
  // A TLS peer that completes TLS but never says Hello is closed at the deadline too.
  testing::RawControlPeer silent(host->tcpPort());
  EXPECT_TRUE(silent.closedByHost());
  EXPECT_TRUE(QTest::qWaitFor([&] { return stillOpen(sockets) == 0; }, kWaitMs));
  EXPECT_GE(host->counters().refusalsFor(RefuseReason::ProtocolError), 3u);  // "handshake timed out"
  auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest")));
  EXPECT_TRUE(settle(*honest)) << honest->errorText().toStdString();
}

TEST_F(Security, StrangerCannotJoinSeeTheModelOrMoveIt) {
  auto host = startHost();
  auto member = start(clientOptions(host->tcpPort(), QStringLiteral("member")));
  ASSERT_TRUE(settle(*member)) << member->errorText().toStdString();
  // Wrong password, and no password: refused with the reason.
  auto guesser = start(clientOptions(host->tcpPort(), QStringLiteral("guesser"), QStringLiteral("hunter2")));
  EXPECT_FALSE(settle(*guesser));
  EXPECT_EQ(guesser->errorText(), QStringLiteral("wrong password"));
  auto blank = start(clientOptions(host->tcpPort(), QStringLiteral("blank"), std::nullopt));
  EXPECT_FALSE(settle(*blank));
  EXPECT_TRUE(blank->errorText().contains(QStringLiteral("password")));
  EXPECT_TRUE(guesser->levelPayload().isEmpty() && blank->levelPayload().isEmpty());
  // A hand-made stranger skips the proof: asks for the model, takes the lock, drags. Refused, closed, nothing sent.
  testing::RawControlPeer stranger(host->tcpPort());
  ASSERT_TRUE(stranger.connected());
  stranger.send(Hello{kProtocolVersion, QStringLiteral("stranger")});
  ASSERT_TRUE(stranger.take<Challenge>());
  stranger.send(ResolutionRequest{});
  stranger.send(LockMessage{LockRequestKind::Request, kNoEpoch});
  stranger.send(Drag{1, {HandleTransform{}}});
  EXPECT_TRUE(stranger.closedByHost());
  EXPECT_FALSE(stranger.take<ModelBegin>(0));
  EXPECT_FALSE(stranger.take<PeerList>(0));
  EXPECT_FALSE(stranger.take<Welcome>(0));
  EXPECT_FALSE(stranger.take<ModelChunk>(0));
  EXPECT_EQ(host->counters().dragsAccepted, 0u);
  EXPECT_EQ(host->lockHolder(), kNoPeer);
  EXPECT_TRUE(host->coefficients().isZero());
  EXPECT_EQ(members(*host), 1u);
  EXPECT_EQ(member->state(), SessionClient::State::Ready);
}

TEST_F(Security, HostSendsNoDatagramToAnAddressThatDidNotProveItsToken) {
  auto host = startHost();
  auto member = start(clientOptions(host->tcpPort(), QStringLiteral("member")));
  ASSERT_TRUE(settle(*member)) << member->errorText().toStdString();
  QUdpSocket stranger;
  ASSERT_TRUE(stranger.bind(QHostAddress::LocalHost, 0));
  qint64 receivedBytes = 0;
  QObject::connect(&stranger, &QUdpSocket::readyRead, &stranger, [&] {
    while (stranger.hasPendingDatagrams()) receivedBytes += stranger.receiveDatagram().data().size();
  });
  // A PathOpen for the member's peer id with a guessed token and key, one with garbage, one replayed-looking.
  const PeerId id = member->peerId();
  const QByteArray forged = encodePathOpen(id, QByteArray(kPathTokenSize, '\x01'), 1, QByteArray(32, '\x02'));
  qint64 sentBytes = 0;
  for (int i = 0; i < 50; ++i) {
    sentBytes += stranger.writeDatagram(forged, QHostAddress::LocalHost, host->udpPort());
    sentBytes +=
        stranger.writeDatagram(QByteArray(100, static_cast<char>(i)), QHostAddress::LocalHost, host->udpPort());
  }
  const std::uint64_t framesBefore = host->counters().framesSent;
  QTest::qWait(1000);
  EXPECT_GT(host->counters().framesSent, framesBefore + 5);  // the host kept sending frames to the member
  EXPECT_GT(sentBytes, 0);
  EXPECT_EQ(receivedBytes, 0);  // amplification factor 0: not one byte back to the unproven address
  std::uint64_t dropped = 0;
  for (int r = 1; r < static_cast<int>(PathOpenError::Count); ++r) {
    dropped += host->channel().drops(static_cast<PathOpenError>(r));
  }
  EXPECT_EQ(dropped, 100u);
  EXPECT_TRUE(host->channel().pathOpen(id));  // the member's path was not moved
}

}  // namespace
}  // namespace sc::session
