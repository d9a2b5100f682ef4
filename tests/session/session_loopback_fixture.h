#pragma once
// The fixture of session_loopback_tests (the session_loopback_*_test.cpp files): a generated mesh (icosphere, 162
// vertices) with a 20-function harmonic basis shared by the suite, a host on 127.0.0.1 with fast password hashing,
// clients joining it, and the cap constraints and lifts the drag tests use.

#include "harmonic_host_model.h"
#include "loopback_session.h"
#include "model/decimating_level_builder.h"
#include "raw_control_peer.h"
#include "session/net/session_client.h"
#include "session/net/session_host.h"
#include "session/wire/handle_transforms.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QtCore/QByteArray>
#include <QtTest/QTest>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace sc::session {

using testing::kWaitMs;

/// A hand-made peer speaking TLS and raw control messages (tests/session/raw_control_peer.h).
using RawPeer = testing::RawControlPeer;

class SessionLoopback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_model = testing::harmonicHostModel(sc::testing::icosphere(2), 20);
    ASSERT_EQ(s_model->rowCount(), 20);
  }
  static void TearDownTestSuite() { s_model.reset(); }

  /// 127.0.0.1, any port, host name "Hostess", 1000 PBKDF2 iterations (fast tests; production keeps the default).
  static SessionHostOptions hostOptions() {
    SessionHostOptions options;
    options.levelBuilder =
        session::LevelBuilder{model::levelTargetList, model::decimatedLevel};  // the suite checks the ladder of levels
    options.address = QHostAddress::LocalHost;
    options.pbkdf2Iterations = 1000;
    options.hostName = QStringLiteral("Hostess");
    return options;
  }

  /// A started host of the suite's model (a failed start is a test failure).
  static std::unique_ptr<SessionHost> startHost(SessionHostOptions options = hostOptions()) {
    return testing::startHost(s_model, std::move(options));
  }

  /// A started client of `host` asking for `level` vertices (0: full), not yet Ready.
  static std::unique_ptr<SessionClient> connectClient(const SessionHost& host, const QString& name,
                                                      std::uint32_t level = 0,
                                                      std::optional<QString> password = std::nullopt) {
    SessionClientOptions options = testing::clientOptions(host.tcpPort(), name, std::move(password));
    options.level = level;
    return testing::startClient(std::move(options));
  }

  /// Waits until the client has its level (Ready) or ended; true when Ready.
  static bool waitReady(SessionClient& client) { return testing::settle(client); }

  /// A client of `host` that is Ready (else a test failure, with its error).
  static std::unique_ptr<SessionClient> join(const SessionHost& host, const QString& name, std::uint32_t level = 0) {
    auto client = connectClient(host, name, level);
    EXPECT_TRUE(waitReady(*client)) << name.toStdString() << ": " << client->errorText().toStdString();
    return client;
  }

  static std::uint32_t n() { return static_cast<std::uint32_t>(s_model->vertexCount()); }

  /// Handle: the cap z > 0.8; anchors: z < −0.5.
  static std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>> capConstraints() {
    std::vector<std::uint32_t> handle, anchors;
    for (Eigen::Index i = 0; i < s_model->V.rows(); ++i) {
      if (s_model->V(i, 2) > 0.8) handle.push_back(static_cast<std::uint32_t>(i));
      if (s_model->V(i, 2) < -0.5) anchors.push_back(static_cast<std::uint32_t>(i));
    }
    return {handle, anchors};
  }

  /// The host takes the lock, sets capConstraints() and lifts the cap by 0.4 along z, then waits for the still frame
  /// that follows (its Z is the host's coefficients() from then on). Assert with ASSERT_NO_FATAL_FAILURE.
  static void liftTheCapAndWaitForTheStillFrame(SessionHost& host) {
    ASSERT_TRUE(host.requestLock());
    ASSERT_EQ(host.lockHolder(), kHostPeer);
    const auto [handle, anchors] = capConstraints();
    spectral::ConstraintSet set;
    set.handles.push_back({std::vector<int>(handle.begin(), handle.end())});
    set.anchors.assign(anchors.begin(), anchors.end());
    ASSERT_TRUE(host.setConstraints(set));
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.0, 0.4);
    ASSERT_TRUE(host.drag(std::span(&pose, 1)));
    ASSERT_TRUE(QTest::qWaitFor([&] { return host.counters().stillFramesSent == 1; }, kWaitMs));
    ASSERT_GT(host.coefficients().norm(), 0.0);
  }

  /// The wire pose of handle 0 translated by `dz` along z.
  static HandleTransform lift(double dz) {
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.0, dz);
    return toWire(0, pose);
  }

  static inline std::shared_ptr<const HostModel> s_model;
};

/// The bytes of an encoded payload as a QByteArray (to compare with what a client received).
inline QByteArray toBytes(const std::vector<std::byte>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size())};
}

}  // namespace sc::session
