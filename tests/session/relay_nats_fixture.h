#pragma once
// Fixture of the relay suites with a real broker (issue 18): a nats-server started per test on 127.0.0.1 and stopped
// by its PID (src/session/net/local_nats_server.h; with TLS in a derived fixture), a started SessionHost of a small
// model with a fresh TLS identity, its RelayPublisher, and viewers with the viewer credential pinned to the host's
// fingerprint. The host's own user drives frames (lock, cap constraints, one drag per frame).
#include "harmonic_host_model.h"
#include "session/net/local_nats_server.h"
#include "session/net/relay_publisher.h"
#include "session/net/relay_viewer.h"
#include "session/net/session_host.h"
#include "session/net/tls_identity.h"
#include "spectral/display_level.h"
#include "spectral/quantized_basis.h"

#include <gtest/gtest.h>

#include <QtCore/QElapsedTimer>
#include <QtTest/QTest>

#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace sc::session {

class RelayNats : public ::testing::Test {
 protected:
  static constexpr int kWaitMs = 5000;
  static constexpr int kDragSpacingMs = 40;  ///< above the host's coalescing: one frame per drag

  static void SetUpTestSuite() { s_model = testing::harmonicHostModel(sc::testing::icosphere(2), 20); }
  static void TearDownTestSuite() { s_model.reset(); }

  void SetUp() override {
    if (!natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
    configureServer(m_server);
    QString error;
    ASSERT_TRUE(m_server.start(&error)) << error.toStdString();
    SessionHostOptions options;
    options.address = QHostAddress::LocalHost;
    options.identity = std::make_shared<const TlsIdentity>(*generateTlsIdentity(QStringLiteral("relay-test")));
    configureHost(options);
    m_host = std::make_unique<SessionHost>(s_model, std::move(options));
    ASSERT_TRUE(m_host->start(&error)) << error.toStdString();
    m_publisher = std::make_unique<RelayPublisher>(*m_host, publisherOptions());
    ASSERT_TRUE(m_publisher->start(&error)) << error.toStdString();
    ASSERT_TRUE(m_host->requestLock());
    spectral::ConstraintSet set;
    std::vector<int> handle;
    for (Eigen::Index i = 0; i < s_model->V.rows(); ++i) {
      if (s_model->V(i, 2) > 0.8) handle.push_back(static_cast<int>(i));
      if (s_model->V(i, 2) < -0.5) set.anchors.push_back(static_cast<int>(i));
    }
    set.handles.push_back({handle});
    ASSERT_TRUE(m_host->setConstraints(set));
  }

  /// A derived fixture's changes to the host's options (relay_level_nats_test.cpp: a ladder of levels).
  virtual void configureHost(SessionHostOptions& /*options*/) {}
  /// A derived fixture's changes to the server before it starts (relay_tls_nats_test.cpp: TLS).
  virtual void configureServer(LocalNatsServer& /*server*/) {}

  void TearDown() override {
    m_viewers.clear();
    m_publisher.reset();
    m_host.reset();
    m_server.stop();
  }

  RelayPublisherOptions publisherOptions() const {
    RelayPublisherOptions options;
    options.nats.url = m_server.url();
    options.nats.user = m_server.config().hostUser;
    options.nats.password = m_server.config().hostPassword;
    options.nats.caFile = m_server.caFile();  // empty without TLS
    options.sessionId = m_server.config().sessionId;
    return options;
  }

  NatsConnectOptions viewerCredential() const {
    NatsConnectOptions options;
    options.url = m_server.url();
    options.user = m_server.config().viewerUser;
    options.password = m_server.config().viewerPassword;
    options.caFile = m_server.caFile();
    return options;
  }

  /// A started viewer pinned to the host (a failed start is a test failure; nullptr then).
  RelayViewer* addViewer(int pendingLimit = 8, Concealment concealment = Concealment::HoldLast) {
    RelayViewerOptions options;
    options.nats = viewerCredential();
    options.sessionId = m_server.config().sessionId;
    options.pin = m_host->fingerprint();
    options.pendingLimit = pendingLimit;
    options.statsEvery = std::chrono::milliseconds(200);
    options.concealment = concealment;
    options.referenceEvery = std::chrono::milliseconds(100);  // read only once a level is set (setLevel)
    auto viewer = std::make_unique<RelayViewer>(std::move(options));
    QString error;
    EXPECT_TRUE(viewer->start(&error)) << error.toStdString();
    m_viewers.push_back(std::move(viewer));
    return m_viewers.back().get();
  }

  /// The host's full model as a viewer's level (X̂ = V, K = H quantised): what distortion is measured at.
  static spectral::SharedDisplayLevel fullLevel() {
    spectral::ResolutionLevel level;
    level.restV = s_model->V;
    level.F = s_model->F;
    level.K = spectral::quantizeBasis(s_model->basis.vectors);
    return spectral::makeDisplayLevel(std::move(level));
  }

  /// One drag of the cap by `dz`, then the event loop for kDragSpacingMs: one frame.
  void dragOnce(double dz) {
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.0, dz);
    ASSERT_TRUE(m_host->drag(std::span(&pose, 1)));
    QTest::qWait(kDragSpacingMs);
  }

  /// Processes events until `done` or kWaitMs.
  static bool waitFor(const std::function<bool()>& done, int ms = kWaitMs) {
    QElapsedTimer clock;
    clock.start();
    while (!done() && clock.elapsed() < ms) QTest::qWait(5);
    return done();
  }

  /// True once `viewer` applied the host's current frame.
  bool caughtUp(const RelayViewer& viewer) const { return viewer.receiver().frame() == m_host->currentFrame(); }

  static inline std::shared_ptr<const HostModel> s_model;
  LocalNatsServer m_server;
  std::unique_ptr<SessionHost> m_host;
  std::unique_ptr<RelayPublisher> m_publisher;
  std::vector<std::unique_ptr<RelayViewer>> m_viewers;
};

}  // namespace sc::session
