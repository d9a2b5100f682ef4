// Tests for the handshake state machines (src/session/engine/handshake_host.cpp, handshake_client.cpp). Host and client
// are wired in memory through the real byte path: encodeControlMessage → ControlFrameReader → decode. No sockets.
#include "session/engine/handshake_client.h"
#include "session/engine/handshake_host.h"

#include <gtest/gtest.h>

#include <memory>

#include "session/wire/control_frame.h"
#include "session/wire/password_auth.h"

namespace sc::session {
namespace {

constexpr std::uint32_t kTestIterations = 16;  // PBKDF2 rounds: small so the tests stay fast
constexpr Millis kStart{1000};

/// Deterministic random source: consecutive bytes of a counter shared by every copy.
RandomBytes countingRandom(std::shared_ptr<int> counter = std::make_shared<int>(0)) {
  return [counter](int count) {
    QByteArray bytes(count, '\0');
    for (int i = 0; i < count; ++i) bytes[i] = static_cast<char>((*counter)++ * 37 + 11);
    return bytes;
  };
}

HostHandshakeConfig hostConfig(std::optional<QString> password = std::nullopt, PeerId peer = 7) {
  HostHandshakeConfig config;
  config.random = countingRandom();
  if (password) config.secret = makeSessionSecret(*password, kTestIterations, config.random);
  config.rowCount = 100;
  config.vertexCount = 22982;
  config.peerId = peer;
  return config;
}

/// Encodes messages and decodes them on the other side of an in-memory stream.
std::vector<ControlDecodeResult> transmit(ControlFrameReader& reader, const std::vector<ControlMessage>& messages) {
  for (const ControlMessage& message : messages) {
    const QByteArray frame = encodeControlMessage(message);
    EXPECT_FALSE(frame.isEmpty()) << "message breaks a limit";
    reader.append(frame);
  }
  std::vector<ControlDecodeResult> results;
  while (auto result = reader.next()) results.push_back(std::move(*result));
  return results;
}

/// A host and a client connected by two in-memory byte streams.
struct Link {
  HostHandshake host;
  ClientHandshake client;
  ControlFrameReader toHost;
  ControlFrameReader toClient;
  bool hostClosed = false;
  bool clientClosed = false;
  std::vector<MessageType> seenByClient;

  Link(HostHandshakeConfig hostConfig, ClientHandshakeConfig clientConfig)
      : host(std::move(hostConfig), kStart), client(std::move(clientConfig)) {}

  void run() { sendToHost({client.start()}); }

  void sendToHost(const std::vector<ControlMessage>& messages) {
    if (hostClosed) return;
    for (const ControlDecodeResult& result : transmit(toHost, messages)) {
      const HandshakeOutput out = result.error == ControlError::None ? host.handleMessage(result.message)
                                                                     : host.handleDecodeError(result.error);
      hostClosed = hostClosed || out.close;
      sendToClient(out.send);
    }
  }

  void sendToClient(const std::vector<ControlMessage>& messages) {
    if (clientClosed) return;
    for (const ControlDecodeResult& result : transmit(toClient, messages)) {
      if (result.error == ControlError::None) seenByClient.push_back(messageType(result.message));
      const HandshakeOutput out = result.error == ControlError::None ? client.handleMessage(result.message)
                                                                     : client.handleDecodeError(result.error);
      clientClosed = clientClosed || out.close;
      sendToHost(out.send);
      if (out.deriveKey) {  // the adapter's worker, here at once
        const PasswordKeyRequest& r = *out.deriveKey;
        sendToHost(client.keyDerived(derivePasswordKey(r.password, r.salt, r.iterations)).send);
      }
    }
  }
};

ClientHandshakeConfig clientConfig(std::optional<QString> password = std::nullopt) {
  return ClientHandshakeConfig{QString::fromUtf8("Zoë"), std::move(password), {}, kTestIterations};
}

void expectJoined(const Link& link) {
  ASSERT_EQ(link.host.state(), HostHandshake::State::Welcomed);
  ASSERT_EQ(link.client.state(), ClientHandshake::State::Joined);
  ASSERT_TRUE(link.host.peer() && link.client.session());
  const NegotiatedPeer& peer = *link.host.peer();
  const Welcome& welcome = *link.client.session();
  EXPECT_EQ(peer.name, QString::fromUtf8("Zoë"));
  EXPECT_EQ(welcome.peerId, 7u);
  EXPECT_EQ(peer.peerId, welcome.peerId);
  EXPECT_EQ(peer.datagramKey, welcome.datagramKey);
  EXPECT_EQ(peer.pathToken, welcome.pathToken);
  EXPECT_EQ(welcome.datagramKey.size(), kDatagramKeySize);
  EXPECT_EQ(welcome.pathToken.size(), kPathTokenSize);
  EXPECT_EQ(welcome.rowCount, 100);
  EXPECT_EQ(welcome.vertexCount, 22982u);
  EXPECT_FALSE(link.hostClosed || link.clientClosed);
  EXPECT_EQ(link.client.failure(), ClientFailure::None);
  EXPECT_FALSE(link.host.refusal());
}

/// Both sides end refused with `reason`; the client got exactly one Refused (after `before`) and shows its text.
void expectRefused(const Link& link, RefuseReason reason, std::vector<MessageType> before = {}) {
  ASSERT_EQ(link.host.state(), HostHandshake::State::Refused);
  ASSERT_TRUE(link.host.refusal());
  EXPECT_EQ(link.host.refusal()->reason, reason);
  EXPECT_TRUE(link.hostClosed);
  EXPECT_FALSE(link.host.peer());
  ASSERT_EQ(link.client.state(), ClientHandshake::State::Refused);
  EXPECT_EQ(link.client.failure(), ClientFailure::RefusedByHost);
  ASSERT_TRUE(link.client.refusal());
  EXPECT_EQ(*link.client.refusal(), *link.host.refusal());
  EXPECT_EQ(link.client.errorText(), link.host.refusal()->text);
  EXPECT_FALSE(link.client.errorText().isEmpty());
  EXPECT_TRUE(link.clientClosed);
  before.push_back(MessageType::Refused);
  EXPECT_EQ(link.seenByClient, before);
}

TEST(Handshake, OpenSessionJoinsWithoutChallenge) {
  Link link(hostConfig(), clientConfig());
  link.run();
  expectJoined(link);
  EXPECT_EQ(link.seenByClient, std::vector<MessageType>{MessageType::Welcome});
}

TEST(Handshake, OpenSessionIgnoresAPasswordTheClientHappensToHave) {
  Link link(hostConfig(), clientConfig(QStringLiteral("secret")));
  link.run();
  expectJoined(link);
}

TEST(Handshake, RightPasswordJoins) {
  Link link(hostConfig(QStringLiteral("correct horse")), clientConfig(QStringLiteral("correct horse")));
  EXPECT_TRUE(link.client.holdsPassword());
  link.run();
  expectJoined(link);
  EXPECT_EQ(link.seenByClient, (std::vector<MessageType>{MessageType::Challenge, MessageType::Welcome}));
  EXPECT_FALSE(link.client.holdsPassword());  // dropped once the proof was made (it was kept for the session's life)
}

TEST(Handshake, WrongPasswordIsRefusedAndTheReasonReachesTheClient) {
  Link link(hostConfig(QStringLiteral("correct horse")), clientConfig(QStringLiteral("battery staple")));
  link.run();
  expectRefused(link, RefuseReason::WrongPassword, {MessageType::Challenge});
  EXPECT_EQ(link.client.errorText(), QStringLiteral("wrong password"));
}

TEST(Handshake, PasswordProofIsBoundToTheHostCertificate) {
  // Same password, same binding: joins. Right password but the client saw another certificate (a relay that
  // terminated its TLS): the proof does not verify on the host.
  const QByteArray hostCertificate(32, '\x11');
  HostHandshakeConfig bound = hostConfig(QStringLiteral("correct horse"));
  bound.channelBinding = hostCertificate;
  ClientHandshakeConfig honest = clientConfig(QStringLiteral("correct horse"));
  honest.channelBinding = hostCertificate;
  Link good(bound, honest);
  good.run();
  expectJoined(good);

  ClientHandshakeConfig relayed = clientConfig(QStringLiteral("correct horse"));
  relayed.channelBinding = QByteArray(32, '\x22');
  Link bad(std::move(bound), std::move(relayed));
  bad.run();
  expectRefused(bad, RefuseReason::WrongPassword, {MessageType::Challenge});
}

TEST(Handshake, ClientWithoutPasswordOnAProtectedSessionGetsAClearLocalError) {
  Link link(hostConfig(QStringLiteral("correct horse")), clientConfig());
  link.run();
  EXPECT_EQ(link.client.state(), ClientHandshake::State::Refused);
  EXPECT_EQ(link.client.failure(), ClientFailure::PasswordRequired);
  EXPECT_FALSE(link.client.refusal());
  EXPECT_TRUE(link.client.errorText().contains(QStringLiteral("password")));
  EXPECT_TRUE(link.clientClosed);
  // The host still waits for a response; the adapter drops it when the socket closes (or the timeout does).
  EXPECT_EQ(link.host.state(), HostHandshake::State::AwaitResponse);
}

TEST(Handshake, VersionMismatchIsRefusedBeforeAnyChallenge) {
  // Our encoder writes only our version, so an older (version 2: datagrams without the extended sequence) and a
  // future client's Hello are spelled out: L = 6, type 0x40, magic, version, and a byte a later version might add
  // (the host must not read past the version).
  // The version just before ours (5: float32 K in the level payload) is the old client a user meets first.
  for (const std::uint8_t version : {std::uint8_t{2}, static_cast<std::uint8_t>(kProtocolVersion - 1),
                                     static_cast<std::uint8_t>(kProtocolVersion + 1)}) {
    Link link(hostConfig(QStringLiteral("pw")), clientConfig(QStringLiteral("pw")));
    link.client.start();  // the client's own Hello is replaced by the raw one below
    link.toHost.append(QByteArray::fromHex("00000005405343") + QByteArray(1, static_cast<char>(version)) +
                       QByteArray::fromHex("ff"));
    link.sendToHost({});
    expectRefused(link, RefuseReason::VersionMismatch);  // no Challenge before the Refused
    ASSERT_TRUE(link.client.refusal());
    EXPECT_EQ(link.client.refusal()->hostVersion, kProtocolVersion);
    EXPECT_TRUE(link.client.errorText().contains(QStringLiteral("version %1").arg(kProtocolVersion)));
    EXPECT_TRUE(link.client.errorText().contains(QStringLiteral("version %1").arg(version)));
  }
}

TEST(Handshake, SessionFullIsRefused) {
  HostHandshakeConfig host = hostConfig(QStringLiteral("pw"));
  host.sessionFull = [] { return true; };
  Link link(std::move(host), clientConfig(QStringLiteral("pw")));
  link.run();
  expectRefused(link, RefuseReason::SessionFull, {MessageType::Challenge});  // told only after the proof
}

TEST(Handshake, AStrangerLearnsNeitherFullnessNorNamesBeforeTheProof) {
  HostHandshakeConfig host = hostConfig(QStringLiteral("pw"));
  host.sessionFull = [] { return true; };
  host.nameTaken = [](const QString&) { return true; };
  Link link(std::move(host), clientConfig(QStringLiteral("guess")));
  link.run();
  expectRefused(link, RefuseReason::WrongPassword, {MessageType::Challenge});
}

TEST(Handshake, BlankOrControlCharacterNamesAreRefused) {
  for (const QString& name : {QStringLiteral("   "), QString(), QStringLiteral("a\nb"), QStringLiteral("x\u0007")}) {
    Link link(hostConfig(), ClientHandshakeConfig{name, std::nullopt, {}, kTestIterations});
    link.run();
    expectRefused(link, RefuseReason::BadName);
  }
}

TEST(Handshake, ATakenNameIsRefused) {
  HostHandshakeConfig host = hostConfig();
  host.nameTaken = [](const QString& name) { return name == QString::fromUtf8("Zoë"); };
  Link link(std::move(host), clientConfig());
  link.run();
  expectRefused(link, RefuseReason::BadName);
  EXPECT_TRUE(link.client.errorText().contains(QString::fromUtf8("Zoë")));
}

/// Feeds `messages` to a fresh host through the byte path; returns the host and the last output.
void expectProtocolError(HostHandshake& host, const std::vector<ControlMessage>& messages) {
  ControlFrameReader reader;
  HandshakeOutput last;
  for (const ControlDecodeResult& result : transmit(reader, messages)) {
    ASSERT_EQ(result.error, ControlError::None);
    last = host.handleMessage(result.message);
  }
  EXPECT_EQ(host.state(), HostHandshake::State::Refused);
  ASSERT_TRUE(host.refusal());
  EXPECT_EQ(host.refusal()->reason, RefuseReason::ProtocolError);
  EXPECT_TRUE(last.close);
  ASSERT_EQ(last.send.size(), 1u);
  EXPECT_EQ(last.send.front(), ControlMessage{*host.refusal()});
}

TEST(Handshake, ChallengeResponseFirstIsAProtocolError) {
  HostHandshake host(hostConfig(QStringLiteral("pw")), kStart);
  expectProtocolError(host, {ChallengeResponse{QByteArray(kMacSize, 'x')}});
}

TEST(Handshake, ASecondHelloIsAProtocolError) {
  HostHandshake host(hostConfig(QStringLiteral("pw")), kStart);
  const Hello hello{kProtocolVersion, QStringLiteral("a")};
  expectProtocolError(host, {hello, hello});
}

TEST(Handshake, ADragBeforeWelcomeIsAProtocolError) {
  HostHandshake open(hostConfig(), kStart);
  expectProtocolError(open, {Drag{1, {}}});
  HostHandshake protectedHost(hostConfig(QStringLiteral("pw")), kStart);
  expectProtocolError(protectedHost, {Hello{kProtocolVersion, QStringLiteral("a")}, Drag{1, {}}});
}

TEST(Handshake, AnUndecodableFrameIsAProtocolError) {
  HostHandshake host(hostConfig(), kStart);
  ControlFrameReader reader;
  reader.append(QByteArray::fromHex("000000017f"));  // L = 1, type 0x7f: unknown
  const auto result = reader.next();
  ASSERT_TRUE(result);
  ASSERT_EQ(result->error, ControlError::UnknownType);
  const HandshakeOutput out = host.handleDecodeError(result->error);
  EXPECT_TRUE(out.close);
  EXPECT_EQ(host.state(), HostHandshake::State::Refused);
  EXPECT_EQ(host.refusal()->reason, RefuseReason::ProtocolError);
}

TEST(Handshake, ClientRefusesUnexpectedHostMessages) {
  ClientHandshake client(clientConfig(QStringLiteral("pw")));
  const HandshakeOutput early = client.handleMessage(Welcome{});
  EXPECT_TRUE(early.close);
  EXPECT_EQ(client.failure(), ClientFailure::ProtocolError);

  ClientHandshake twice(clientConfig(QStringLiteral("pw")));
  twice.start();
  const Challenge challenge{QByteArray(kNonceSize, 'n'), QByteArray(kSaltSize, 's'), kTestIterations};
  const HandshakeOutput first = twice.handleMessage(challenge);
  EXPECT_TRUE(first.send.empty() && first.deriveKey.has_value());  // the key is derived before anything is sent
  EXPECT_TRUE(twice.handleMessage(challenge).close);               // a second Challenge, while deriving
  EXPECT_TRUE(twice.keyDerived(QByteArray(kMacSize, 'k')).send.empty()) << "a key after the end is ignored";
  EXPECT_EQ(twice.state(), ClientHandshake::State::Refused);
  EXPECT_EQ(twice.failure(), ClientFailure::ProtocolError);

  ClientHandshake keyframe(clientConfig());
  keyframe.start();
  EXPECT_TRUE(keyframe.handleMessage(Keyframe{1, {0, 0, 0}}).close);
  EXPECT_EQ(keyframe.failure(), ClientFailure::ProtocolError);
}

TEST(Handshake, TimeoutRefusesAtTickStrictlyAfterTheLimit) {
  HostHandshake host(hostConfig(QStringLiteral("pw")), kStart);
  host.handleMessage(Hello{kProtocolVersion, QStringLiteral("slow")});
  ASSERT_EQ(host.state(), HostHandshake::State::AwaitResponse);
  EXPECT_FALSE(host.tick(kStart + kHandshakeTimeout).close);
  const HandshakeOutput out = host.tick(kStart + kHandshakeTimeout + Millis{1});
  EXPECT_TRUE(out.close);
  ASSERT_EQ(out.send.size(), 1u);
  EXPECT_EQ(host.state(), HostHandshake::State::Refused);
  EXPECT_EQ(host.refusal()->reason, RefuseReason::ProtocolError);
  EXPECT_TRUE(host.refusal()->text.contains(QStringLiteral("timed out")));
  EXPECT_TRUE(host.tick(kStart + Millis{60000}).send.empty());  // final: once only
}

TEST(Handshake, AWelcomedPeerDoesNotTimeOut) {
  Link link(hostConfig(), clientConfig());
  link.run();
  const HandshakeOutput out = link.host.tick(kStart + Millis{60000});
  EXPECT_FALSE(out.close);
  EXPECT_TRUE(out.send.empty());
  expectJoined(link);
}

TEST(Handshake, DistinctPeersGetDistinctKeysAndTokensDeterministically) {
  auto joinTwo = [] {
    const RandomBytes random = countingRandom();
    std::vector<NegotiatedPeer> peers;
    for (PeerId id : {PeerId{1}, PeerId{2}}) {
      HostHandshakeConfig config = hostConfig(std::nullopt, id);
      config.random = random;
      Link link(std::move(config), clientConfig());
      link.run();
      EXPECT_EQ(link.client.state(), ClientHandshake::State::Joined);
      peers.push_back(link.host.peer().value_or(NegotiatedPeer{}));
    }
    return peers;
  };
  const std::vector<NegotiatedPeer> peers = joinTwo();
  EXPECT_EQ(peers[0].peerId, 1u);
  EXPECT_EQ(peers[1].peerId, 2u);
  EXPECT_NE(peers[0].datagramKey, peers[1].datagramKey);
  EXPECT_NE(peers[0].pathToken, peers[1].pathToken);
  EXPECT_EQ(joinTwo(), peers);  // same injected source, same keys
}

}  // namespace
}  // namespace sc::session
