// A malicious host against the socket-free client rules (docs/security.md, "Hostile host"): announcements the level
// list does not imply, absurd session shapes, weak password challenges, absurd levels and coefficients. Every one
// is refused with a readable reason before the client allocates for it. A fake host on the fake clock (no sockets).
#include "client_engine_fixture.h"

#include "session/wire/password_auth.h"

#include <limits>

namespace sc::session::test {
namespace {

constexpr std::uint32_t k512MiB = 512u << 20;

class ClientEngineHostile : public ::testing::Test {
 protected:
  void SetUp() override { joinSession(engine, kT0); }
  /// Feeds one message at kT0.
  ClientActions feed(ControlMessage m) { return engine.onMessage(message(std::move(m)), kT0); }
  ClientEngine engine{config("victim")};
};

TEST_F(ClientEngineHostile, AnAnnouncementTheLevelListDoesNotImplyFailsTheSessionBeforeAnyByte) {
  const auto honest = static_cast<std::uint32_t>(tinyPayload("").size());
  feed(tinyLevelList(honest));
  const ClientActions out = feed(ModelBegin{1, TransferKind::FullModel, kVertices, k512MiB, sha256("x")});
  EXPECT_EQ(engine.state(), ClientState::Failed);
  EXPECT_TRUE(engine.errorText().contains(QStringLiteral("level list"))) << engine.errorText().toStdString();
  EXPECT_TRUE(actionsOf<client_action::ModelProgress>(out).empty()) << "no transfer was started";
}

TEST_F(ClientEngineHostile, AnAnnouncementBeforeAnyLevelListFailsTheSession) {
  feed(ModelBegin{1, TransferKind::FullModel, kVertices, 200, sha256("x")});
  EXPECT_EQ(engine.state(), ClientState::Failed);
  EXPECT_TRUE(engine.errorText().contains(QStringLiteral("level list"))) << engine.errorText().toStdString();
}

TEST_F(ClientEngineHostile, ALevelListWhosePayloadSizeItsCountsDoNotImplyFailsTheSession) {
  // The measured attack: 3 vertices, 1 face and m = 2 imply a payload of at most 268 bytes, not 512 MiB.
  feed(tinyLevelList(k512MiB));
  EXPECT_EQ(engine.state(), ClientState::Failed);
  EXPECT_TRUE(engine.errorText().contains(QStringLiteral("imply"))) << engine.errorText().toStdString();
}

TEST_F(ClientEngineHostile, ALevelListWithMoreVerticesThanTheSessionFailsIt) {
  feed(LevelList{1, {LevelInfo{0, 100'000, 200'000, 100'000}}});
  EXPECT_EQ(engine.state(), ClientState::Failed);
  EXPECT_FALSE(engine.errorText().isEmpty());
}

TEST(ClientEngineHostileWelcome, AWelcomeWhoseFullModelCouldNotBeSentIsRefused) {
  ClientEngine engine{config("victim")};
  engine.start();
  engine.onSecured(QByteArray(32, 'c'), kT0);
  Welcome absurd = fakeWelcome();
  absurd.vertexCount = std::numeric_limits<std::uint32_t>::max();
  const ClientActions out = engine.onMessage(message(absurd), kT0);
  EXPECT_TRUE(actionsOf<client_action::OpenDatagrams>(out).empty());
  EXPECT_EQ(engine.state(), ClientState::Failed);
  EXPECT_TRUE(engine.errorText().contains(QStringLiteral("vertices"))) << engine.errorText().toStdString();
}

TEST_F(ClientEngineHostile, ANewAnnouncementDropsTheCompletedTransferThatWaits) {
  const QByteArray first = tinyPayload("first"), second = tinyPayload("second"), third = tinyPayload("third");
  deliverTransfer(engine, first, 1, kT0);   // decoding
  deliverTransfer(engine, second, 2, kT0);  // complete, waits for the decode
  ModelSender sender(3, TransferKind::FullModel, kVertices, third, 64);
  feed(sender.begin());  // at most one transfer in flight: the waiting one is freed
  feed(*sender.nextChunk());
  const ClientActions out = engine.onLevelDecoded(decodedLevel());
  EXPECT_TRUE(actionsOf<client_action::StartDecode>(out).empty()) << "the second transfer was dropped";
  while (std::optional<ModelChunk> chunk = sender.nextChunk()) feed(*chunk);
  EXPECT_TRUE(engine.levelDecoding()) << "the third one decodes once complete";
}

TEST_F(ClientEngineHostile, KeyframesWithAbsurdCoefficientsAreNotSeeded) {
  const ClientActions out = feed(Keyframe{8, {1, 2, 3, 4, 5, 1e300}});
  EXPECT_TRUE(actionsOf<client_action::SeedKeyframe>(out).empty());
  EXPECT_EQ(engine.keyframesReceived(), 0u);
  EXPECT_EQ(engine.state(), ClientState::Loading) << "dropped and counted, like a bad datagram";
}

TEST(ClientHandshakeHostile, AOneIterationChallengeIsRefusedWithoutAProof) {
  ClientHandshake client(
      ClientHandshakeConfig{QStringLiteral("victim"), QStringLiteral("hunter2"), {}, kMinPbkdf2Iterations});
  client.start();
  const HandshakeOutput out =
      client.handleMessage(Challenge{QByteArray(kNonceSize, 'n'), QByteArray(kSaltSize, 's'), 1});
  EXPECT_TRUE(out.send.empty()) << "no proof an impostor could crack at HMAC speed";
  EXPECT_TRUE(out.close);
  EXPECT_EQ(client.state(), ClientHandshake::State::Refused);
  EXPECT_TRUE(client.errorText().contains(QStringLiteral("iterations"))) << client.errorText().toStdString();
}

TEST(ClientHandshakeHostile, TheMinimumIsAcceptedAndTheHostDefaultIsAbove) {
  ClientHandshake client(
      ClientHandshakeConfig{QStringLiteral("victim"), QStringLiteral("hunter2"), {}, kMinPbkdf2Iterations});
  client.start();
  const HandshakeOutput out =
      client.handleMessage(Challenge{QByteArray(kNonceSize, 'n'), QByteArray(kSaltSize, 's'), kMinPbkdf2Iterations});
  ASSERT_TRUE(out.deriveKey.has_value()) << "the key to derive";
  EXPECT_EQ(out.deriveKey->iterations, kMinPbkdf2Iterations);
  EXPECT_EQ(out.deriveKey->password, QStringLiteral("hunter2"));
  EXPECT_FALSE(client.holdsPassword()) << "the request holds the only copy";
  const HandshakeOutput proof =
      client.keyDerived(derivePasswordKey(out.deriveKey->password, out.deriveKey->salt, out.deriveKey->iterations));
  EXPECT_EQ(proof.send.size(), 1u) << "the proof";
  EXPECT_EQ(client.state(), ClientHandshake::State::AwaitWelcome);
  EXPECT_GE(kDefaultPbkdf2Iterations, 600'000u);
}

TEST(ModelReceiverHostile, NeverReservesMoreThanTheAnnouncedSize) {
  const QByteArray payload(3 * kMaxChunkBytes + 1, 'p');
  ModelSender sender(1, TransferKind::FullModel, 3, payload);
  ModelReceiver receiver;
  receiver.begin(sender.begin());
  EXPECT_EQ(receiver.reservedBytes(), 0u) << "nothing before the first chunk";
  while (std::optional<ModelChunk> chunk = sender.nextChunk()) {
    receiver.add(*chunk);
    EXPECT_LE(receiver.reservedBytes(), static_cast<std::uint64_t>(payload.size()));
  }
  EXPECT_EQ(receiver.take(), payload);
}

TEST(ClientLevelDecodeHostile, HugeCoordinatesAreRefused) {
  spectral::ResolutionLevel level = tinyLevel();
  level.restV(1, 2) = 1e300;
  const QByteArray payload = encoded(level);
  const DecodedLevel out = decodeLevel(LevelJob{payload, sha256(payload), kRows, kVertices});
  EXPECT_EQ(out.level, nullptr);
  EXPECT_TRUE(out.error.contains(QStringLiteral("coordinate"))) << out.error.toStdString();
}

TEST(ClientLevelDecodeHostile, AnEmptyLevelIsRefused) {
  spectral::ResolutionLevel level;
  level.restV.resize(0, 3);
  level.F.resize(0, 3);
  level.P.resize(0, kVertices);
  level.K = spectral::quantizeBasis(Eigen::MatrixXd(0, kRows));
  const QByteArray payload = encoded(level);
  const DecodedLevel out = decodeLevel(LevelJob{payload, sha256(payload), kRows, kVertices});
  EXPECT_EQ(out.level, nullptr);
  EXPECT_FALSE(out.error.isEmpty());
}

TEST(ClientLevelDecodeHostile, HugeKernelEntriesAreRefused) {
  const QByteArray payload = encoded(tinyLevel(3e38f));
  const DecodedLevel out = decodeLevel(LevelJob{payload, sha256(payload), kRows, kVertices});
  EXPECT_EQ(out.level, nullptr);
  EXPECT_FALSE(out.error.isEmpty());
}

}  // namespace
}  // namespace sc::session::test
