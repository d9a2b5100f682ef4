// A malicious host against a real SessionClient over TLS on 127.0.0.1 (docs/security.md, "Hostile host"): every
// attack ends in a readable refusal, nothing absurd is shown, and the client's memory stays bounded. The host is
// HostileHost (hostile_host.h), scripted message by message; the session is tiny (m = 2, n = 3: the
// client_engine_fixture.h level), so that sizes are exact and every test takes well under a second.
#include "address_sanitizer.h"
#include "client_engine_fixture.h"
#include "hostile_host.h"
#include "session/net/session_client.h"
#include "session/wire/coefficient_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

namespace sc::session::testing {
namespace {

using test::kRows;
using test::kSelf;
using test::kVertices;

class MaliciousHost : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_identity = std::make_shared<const TlsIdentity>(*generateTlsIdentity(QStringLiteral("impostor")));
  }
  static void TearDownTestSuite() { s_identity.reset(); }

  /// A client of the hostile host with the default (real) limits, started.
  std::unique_ptr<SessionClient> join(std::optional<QString> password = std::nullopt) {
    SessionClientOptions options;
    options.port = host.port();
    options.name = QStringLiteral("victim");
    options.password = std::move(password);
    auto client = std::make_unique<SessionClient>(std::move(options));
    client->start();
    return client;
  }
  /// The Welcome of the tiny session (m = 2, n = 3), datagrams to the hostile host's UDP port.
  Welcome welcome() const {
    Welcome w = test::fakeWelcome();
    w.udpPort = host.udpPort();
    return w;
  }
  /// Hello → Welcome → `levels`; then waits for the client's ResolutionRequest (false if none came).
  bool admit(const LevelList& levels) {
    if (!host.awaitHello()) return false;
    host.send(welcome());
    host.send(levels);
    return host.take<ResolutionRequest>().has_value();
  }
  /// Sends `payload` as a listed full-model transfer.
  void transfer(const QByteArray& payload) {
    ModelSender sender(1, TransferKind::FullModel, kVertices, payload);
    host.send(sender.begin());
    while (std::optional<ModelChunk> chunk = sender.nextChunk()) host.send(*chunk);
  }
  static bool waitFor(SessionClient& client, SessionClient::State state) {
    return QTest::qWaitFor([&] { return client.state() == state; }, kHostileWaitMs);
  }
  static bool allFinite(const Eigen::MatrixXf& Z) { return Z.allFinite(); }

  static inline std::shared_ptr<const TlsIdentity> s_identity;
  HostileHost host{*s_identity};
};

TEST_F(MaliciousHost, AOneIterationChallengeGetsNoProofAndAReadableRefusal) {
  auto client = join(QStringLiteral("correct horse battery staple"));
  ASSERT_TRUE(host.awaitHello());
  host.send(Challenge{QByteArray(kNonceSize, 'n'), QByteArray(kSaltSize, 's'), 1});
  ASSERT_TRUE(waitFor(*client, SessionClient::State::Failed));
  EXPECT_TRUE(client->errorText().contains(QStringLiteral("iterations"))) << client->errorText().toStdString();
  EXPECT_FALSE(host.take<ChallengeResponse>(200)) << "no proof to crack at HMAC speed";
  EXPECT_TRUE(host.clientClosed());
}

TEST_F(MaliciousHost, AWelcomeOfAModelNoTransferCouldCarryIsRefused) {
  auto client = join();
  ASSERT_TRUE(host.awaitHello());
  Welcome absurd = welcome();
  absurd.vertexCount = std::numeric_limits<std::uint32_t>::max();
  host.send(absurd);
  ASSERT_TRUE(waitFor(*client, SessionClient::State::Failed));
  EXPECT_TRUE(client->errorText().contains(QStringLiteral("vertices"))) << client->errorText().toStdString();
  EXPECT_FALSE(host.take<ResolutionRequest>(200));
}

TEST_F(MaliciousHost, AnOversizedAnnouncementIsRefusedBeforeTheClientAllocatesIt) {
  // The measured attack: a level list, then a 512 MiB ModelBegin and its chunks; here 64 MiB of them are offered.
  const auto honest = static_cast<std::uint32_t>(test::tinyPayload("").size());
  auto client = join();
  ASSERT_TRUE(admit(test::tinyLevelList(honest)));
  const std::uint64_t before = residentBytes();
  constexpr std::uint32_t k512MiB = 512u << 20;
  host.send(ModelBegin{1, TransferKind::FullModel, kVertices, k512MiB, QByteArray(kChecksumSize, 'h')});
  const int written = host.streamChunks(1, k512MiB, 1024);
  QTest::qWait(100);  // what the client could still read
  const std::uint64_t after = residentBytes();
  EXPECT_TRUE(waitFor(*client, SessionClient::State::Failed));
  EXPECT_TRUE(client->errorText().contains(QStringLiteral("level list"))) << client->errorText().toStdString();
  EXPECT_LT(written, 1024) << "the client closed the connection";
  // ASan's quarantine keeps freed blocks resident (20 MiB measured in the sanitiser job): a wider bound there, still
  // well under the 64 MiB offered (the unfixed client grew by 72 MiB).
  const std::uint64_t bound = (sc::testing::kAddressSanitizer ? 40u : 16u) << 20;
  EXPECT_LT(after, before + bound) << "resident memory grew by " << (after - before) / (1 << 20) << " MiB";
}

TEST_F(MaliciousHost, ALevelWithHugeCoordinatesIsRefusedAndNothingIsShown) {
  spectral::ResolutionLevel level = test::tinyLevel();
  level.restV(0, 0) = 1e300;
  const QByteArray payload = test::encoded(level);
  auto client = join();
  ASSERT_TRUE(admit(test::tinyLevelList(static_cast<std::uint32_t>(payload.size()))));
  transfer(payload);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !client->levelError().isEmpty(); }, kHostileWaitMs));
  EXPECT_TRUE(client->levelError().contains(QStringLiteral("coordinate"))) << client->levelError().toStdString();
  EXPECT_EQ(client->level(), nullptr);
  EXPECT_EQ(client->state(), SessionClient::State::Loading) << "the connection is kept, nothing is shown";
}

TEST_F(MaliciousHost, HugeCoefficientsAreNeverShown) {
  auto client = join();
  ASSERT_TRUE(admit(test::tinyLevelList(static_cast<std::uint32_t>(test::tinyPayload("").size()))));
  transfer(test::encoded(test::tinyLevel()));
  ASSERT_TRUE(waitFor(*client, SessionClient::State::Ready));
  // A Keyframe of 1e300 (finite in double, infinite in float32) and datagrams whose exponents make 1e40.
  host.send(Keyframe{1, std::vector<double>(3 * kRows, 1e300)});
  CoefficientEncoder encoder(welcome().datagramKey, kSelf);
  ASSERT_TRUE(host.sendDatagrams(encoder.encodeFrame(2, Eigen::MatrixXd::Constant(kRows, 3, 1e40))));
  EXPECT_TRUE(QTest::qWaitFor([&] { return client->peekStats().dropped >= 2; }, kHostileWaitMs))
      << "the Keyframe and the datagram frame are dropped and counted";
  QTest::qWait(50);
  EXPECT_TRUE(allFinite(client->positionsCoefficients()));
  EXPECT_TRUE(client->positionsCoefficients().isZero()) << "the first frame stays shown";
  for (const float x : client->positions()) ASSERT_TRUE(std::isfinite(x));
}

TEST_F(MaliciousHost, ARichTextRefusalReachesTheClientAsTheExactText) {
  // The client treats the host's text as data: it is passed on verbatim (the desktop app shows it as plain text,
  // main_window_session.cpp), never interpreted.
  const QString text =
      QStringLiteral("<a href=\"https://evil.example\">Click to re-enter your password</a><img src=x>");
  auto client = join();
  ASSERT_TRUE(host.awaitHello());
  host.send(Refused{RefuseReason::ShuttingDown, kProtocolVersion, text});
  ASSERT_TRUE(waitFor(*client, SessionClient::State::Failed));
  EXPECT_EQ(client->errorText(), text);
}

}  // namespace
}  // namespace sc::session::testing
