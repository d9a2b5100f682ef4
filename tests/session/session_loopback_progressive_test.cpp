// Loopback test of the progressive join (issue 17 item 4; ClientEngine's rules through SessionHost and
// SessionClient): the host prepares its smallest level from the start, a progressive client shows it first with the
// live deformation, then the requested full model, and the deformation is the same Z across the swap. Real sockets
// on 127.0.0.1. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include "session/net/level_library.h"
#include "spectral/display_level.h"

#include <QtTest/QTest>

#include <map>

namespace sc::session {
namespace {

/// What a client showed on one level: the level and the reconstructed positions (interleaved xyz).
struct Shown {
  spectral::SharedDisplayLevel level;
  std::vector<float> positions;
};

TEST_F(SessionLoopback, ProgressiveJoinShowsTheSmallestLevelThenTheRequestedOneWithTheSameZ) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);  // no refresh frames: one Z for the whole join
  auto host = startHost(options);
  // The smallest level is built from the start, before anybody joins.
  const std::uint32_t smallest = host->levels().smallestTarget();
  ASSERT_LT(smallest, n());
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->levels().find(smallest) != nullptr; }, kWaitMs));
  const std::uint32_t smallVertices = host->levels().find(smallest)->vertexCount;

  // A deformed shape, still: the cap lifted.
  ASSERT_NO_FATAL_FAILURE(liftTheCapAndWaitForTheStillFrame(*host));
  const Eigen::MatrixXd Z = host->coefficients();

  SessionClientOptions clientOptions = testing::clientOptions(host->tcpPort(), QStringLiteral("progressive"));
  clientOptions.progressive = true;
  auto client = testing::startClient(std::move(clientOptions));
  std::vector<std::uint32_t> installed;
  std::vector<bool> pendingAtInstall;
  std::map<std::uint32_t, Shown> shown;  // per level: the last positions shown with the host's Z
  QObject::connect(client.get(), &SessionClient::levelReady, client.get(), [&](std::uint32_t vertices) {
    installed.push_back(vertices);
    pendingAtInstall.push_back(client->levelPending());
  });
  QObject::connect(client.get(), &SessionClient::positionsUpdated, client.get(), [&](std::uint32_t) {
    if (!client->channel().hasFrame() || client->channel().coefficients() != Z) return;
    const std::vector<float>& positions = client->positions();
    shown[client->levelVertexCount()] = Shown{client->displayLevel(), positions};
  });
  ASSERT_TRUE(QTest::qWaitFor([&] { return installed.size() == 2; }, kWaitMs)) << client->errorText().toStdString();
  EXPECT_EQ(installed, (std::vector<std::uint32_t>{smallVertices, n()})) << "the smallest level first";
  EXPECT_EQ(pendingAtInstall, (std::vector<bool>{true, false}));
  EXPECT_FALSE(client->levelPending());
  EXPECT_EQ(client->levelVertexCount(), n());
  ASSERT_TRUE(shown.contains(smallVertices)) << "the preview was shown deformed";
  ASSERT_TRUE(shown.contains(n())) << "the full model was shown deformed";

  // The same Z on both levels: the preview's displacement from its rest mesh is P times the full model's
  // (X' = X̂' + P·H·Z), within the quantisation of K (13 bits per column); and it is a real deformation.
  const Shown& small = shown[smallVertices];
  const Shown& full = shown[n()];
  const auto displacement = [](const Shown& s) {
    Eigen::MatrixXd d(static_cast<Eigen::Index>(s.positions.size() / 3), 3);
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      for (Eigen::Index c = 0; c < 3; ++c) {
        const auto k = static_cast<std::size_t>(3 * i + c);
        d(i, c) = static_cast<double>(s.positions[k]) - static_cast<double>(s.level->rest[k]);
      }
    }
    return d;
  };
  const Eigen::MatrixXd dSmall = displacement(small);
  const Eigen::MatrixXd dFull = displacement(full);
  const Eigen::MatrixXd expected = small.level->level.P * dFull;
  ASSERT_EQ(dSmall.rows(), expected.rows());
  EXPECT_GT(dSmall.cwiseAbs().maxCoeff(), 0.2) << "the preview shows the deformed shape, not the rest pose";
  EXPECT_LT((dSmall - expected).cwiseAbs().maxCoeff(), 2e-3) << "the same Z on the finer level";
  EXPECT_EQ(client->channel().coefficients(), Z) << "no jump back to rest across the swap";
}

}  // namespace
}  // namespace sc::session
